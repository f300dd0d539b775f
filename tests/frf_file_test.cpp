// Tests of measured-FRF file handling: ordinate conversion checked against the closed-form
// receptance of a single-DOF oscillator (mobility and accelerance built from the formula, not by
// the code under test), the dataset 164 units rule of the UFF specification, a real FRF file
// exported by measurement software, the CutPro text format, dispatch by extension (the
// `toolpoint convert` command's exit codes and files: cli_files_test.cpp).
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <unistd.h>

#include "toolpoint/conventions.hpp"
#include "toolpoint/error.hpp"
#include "toolpoint/io/frf_file.hpp"
#include "toolpoint/io/io.hpp"
#include "support/scratch.hpp"

using namespace toolpoint;
namespace fs = std::filesystem;

using uff_test::any_contains;
using uff_test::contains;

namespace {

const std::string kUffDir = std::string(TOOLPOINT_TEST_DATA_DIR) + "/uff/";

using test::TempDir;

// Single-DOF oscillator: H(f) = 1/(k − mω² + icω), m = 2 kg, k = 8e6 N/m, c = 150 N·s/m.
Complex sdof_receptance(double f) {
  const double w = 2.0 * kPi * f;
  return 1.0 / Complex(8e6 - 2.0 * w * w, 150.0 * w);
}

// The one-mode receptance sampled at n points, step `step_hz` apart from `step_hz`.
FrfSeries sdof_series(int n, double step_hz) {
  FrfSeries h;
  for (int i = 1; i <= n; ++i) {
    h.frequency_hz.push_back(step_hz * i);
    h.values.push_back(sdof_receptance(step_hz * i));
  }
  return h;
}

// The same oscillator's mobility Y = iωH and accelerance A = −ω²H as a UFF FRF dataset with the
// given record 9 code (8, 11 or 12), from 0 Hz in 2.5 Hz steps.
UffDataset58 sdof_dataset(int numerator_code, std::size_t n = 400) {
  UffDataset58 d;
  d.id[0] = "SDOF";
  d.function_type = 4;
  d.ordinate_data_type = 6;
  d.abscissa = {18, 0, 0, 0, "Frequency", "Hz"};
  d.ordinate = {numerator_code, 0, 0, 0, "Response", "SI"};
  d.denominator = {13, 0, 0, 0, "Force", "N"};
  d.abscissa_min = 0.0;
  d.abscissa_increment = 2.5;
  for (std::size_t i = 0; i < n; ++i) {
    const double f = 2.5 * static_cast<double>(i), w = 2.0 * kPi * f;
    const Complex h = sdof_receptance(f);
    d.x.push_back(f);
    d.y.push_back(numerator_code == 8 ? h : numerator_code == 11 ? Complex(0.0, w) * h : -w * w * h);
  }
  return d;
}

}  // namespace

// Mobility and accelerance files give back the closed-form receptance. The data are written in
// binary double (exact), so the only error is the rounding of ω = 2πf and one division: 1e-13.
// The 0 Hz point cannot be converted and is dropped with a warning.
TEST(FrfFile, MobilityAndAcceleranceConvertToTheClosedFormReceptance) {
  TempDir dir;
  for (int code : {8, 11, 12}) {
    SCOPED_TRACE(code);
    const std::string path = dir / ("sdof_" + std::to_string(code) + ".uff");
    write_uff(path, {sdof_dataset(code)}, UffWriteOptions{.binary = true});
    const FrfFileData r = read_frf_file(path);
    EXPECT_EQ(r.ordinate, code == 8 ? FrfOrdinate::Receptance : code == 11 ? FrfOrdinate::Mobility : FrfOrdinate::Accelerance);
    ASSERT_EQ(r.single.size(), 399u);
    EXPECT_EQ(r.single.frequency_hz.front(), 2.5);
    for (std::size_t i = 0; i < r.single.size(); ++i) {
      const Complex h = sdof_receptance(r.single.frequency_hz[i]);
      ASSERT_LE(std::abs(r.single.values[i] - h), 1e-13 * std::abs(h)) << r.single.frequency_hz[i];
    }
    EXPECT_TRUE(any_contains(r.warnings, {"1 point(s) at 0 Hz dropped"}));
  }
}

// The override wins over the codes (with a warning when they disagree); codes that say nothing
// useful need the override.
TEST(FrfFile, OrdinateOverride) {
  TempDir dir;
  const std::string path = dir / "acc.uff";
  write_uff(path, {sdof_dataset(12)}, UffWriteOptions{.binary = true});
  const FrfFileData r = read_frf_file(path, {.ordinate = FrfOrdinate::Mobility});
  EXPECT_EQ(r.ordinate, FrfOrdinate::Mobility);
  EXPECT_TRUE(any_contains(r.warnings, {"states accelerance", "mobility was given"}));
  // Taken as mobility, acceleration/(iω) is off from H by the factor iω.
  const double f = r.single.frequency_hz[10], w = 2.0 * kPi * f;
  EXPECT_LE(std::abs(r.single.values[10] - Complex(0.0, w) * sdof_receptance(f)), 1e-12 * w * std::abs(sdof_receptance(f)));

  UffDataset58 general = sdof_dataset(12);
  general.ordinate.data_type = 1;
  write_uff(path, {general});
  try {
    read_frf_file(path);
    FAIL() << "read an ordinate of unknown kind";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "record 9 ordinate data type 1 (general")) << e.what();
    EXPECT_TRUE(contains(e.hint(), "FrfReadOptions::ordinate")) << e.hint();
  }
  EXPECT_NO_THROW(read_frf_file(path, {.ordinate = FrfOrdinate::Accelerance}));
}

// A real FRF exported by measurement software (function type 4, complex single, ordinate code
// "general", units label (1/N)*(m/s²) — a product, as some analysers write it — from 0 Hz). The
// label says accelerance, and it is read so (with a warning that the codes do not say it), as with
// the ordinate given: the 0 Hz point is dropped and H = A/(−ω²) from the printed values
// A(0.195313 Hz) = −5.99924e-2 − 5.53260e-2 i, exact to the rounding of ω (1e-13).
TEST(FrfFile, RealAcceleranceFile) {
  const FrfFileData labelled = read_frf_file(kUffDir + "non_ascii_header.uff");
  EXPECT_EQ(labelled.ordinate, FrfOrdinate::Accelerance);
  EXPECT_TRUE(any_contains(labelled.warnings, {"the units labels ('(1/N)*(m/s²)') say accelerance"}));
  const FrfFileData r = read_frf_file(kUffDir + "non_ascii_header.uff", {.ordinate = FrfOrdinate::Accelerance});
  EXPECT_EQ(labelled.single.values, r.single.values);
  ASSERT_EQ(r.single.size(), 5u);
  const double f = 0.195313, w = 2.0 * kPi * f;
  EXPECT_EQ(r.single.frequency_hz[0], f);
  const Complex h = Complex(-5.99924e-2, -5.53260e-2) / (-w * w);
  EXPECT_LE(std::abs(r.single.values[0] - h), 1e-13 * std::abs(h));
  EXPECT_TRUE(any_contains(r.warnings, {"non_ascii_header.uff", "at 0 Hz dropped", "accelerance"}));
  EXPECT_EQ(r.format, FrfFormat::Uff);
  // A time record is not an FRF.
  try {
    read_frf_file(kUffDir + "Sample_UFF58b_bin.uff");
    FAIL();
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "function type 1 (time response)")) << e.what();
  }
}

// Dataset 164 gives factors from SI to file units (SI value = file value / factor). A receptance
// in mm/N (length factor 1000, force factor 1) is 1/1000 of its value in m/N.
TEST(FrfFile, UnitsDatasetScalesToSi) {
  TempDir dir;
  const std::string path = dir / "mm.uff";
  UffDataset58 d = sdof_dataset(8, 20);
  for (auto& y : d.y) y *= 1000.0;  // mm/N
  const std::string units =
      "    -1\n   164\n         5mm (newton)                 2\n"
      "  1.00000000000000000D+03  1.00000000000000000D+00  1.00000000000000000D+00\n"
      "  2.73149999999999977D+02\n    -1\n";
  write_text_file(path, units + format_uff({d}, {.binary = true}).bytes);
  const FrfFileData r = read_frf_file(path);
  for (std::size_t i = 0; i < r.single.size(); ++i) {
    const Complex h = sdof_receptance(r.single.frequency_hz[i]);
    ASSERT_LE(std::abs(r.single.values[i] - h), 1e-13 * std::abs(h));
  }
  EXPECT_TRUE(any_contains(r.warnings, {"dataset 164 at line 1", "mm (newton)", "× 0.001"}));
  // Without a units dataset, a units label toolpoint knows is applied (mm/N is 1/1000 m/N) …
  d.ordinate.units = "mm/N";
  write_uff(path, {d}, {.binary = true});
  const FrfFileData labelled = read_frf_file(path);
  for (std::size_t i = 0; i < labelled.single.size(); ++i) {
    const Complex h = sdof_receptance(labelled.single.frequency_hz[i]);
    ASSERT_LE(std::abs(labelled.single.values[i] - h), 1e-13 * std::abs(h));
  }
  EXPECT_TRUE(any_contains(labelled.warnings, {"values in 'mm/N' converted to SI", "× 0.001"})) << labelled.warnings.at(0);
  // … and one it does not know is reported, not applied.
  d.ordinate.units = "mm/kgf";
  write_uff(path, {d});
  EXPECT_TRUE(any_contains(read_frf_file(path).warnings, {"'mm/kgf'", "not SI", "FrfReadOptions::units"}));
}

// CutPro text: liberal in layout, strict about what the columns are, strict in what is written.
TEST(FrfFile, CutProTextReadLiberally) {
  const std::string text =
      "% exported by some tool\r\n"
      "Freq\tHz\tReal\tm/N\tImag\tm/N\r\n"
      "0\t1e-6\t0\r\n"
      "10\t1.5e-06\t-2.5e-07\r\n"
      "\r\n"
      "# a comment between data lines\n"
      "20  2.5E-06   -3.5e-07\n"
      "30, 3.5e-6, -4.5e-7\n"
      "40;+4.5e-6;-5.5e-7";
  const FrfText t = parse_cutpro_frf(text, "tap.frf");
  EXPECT_EQ(t.series.frequency_hz, (std::vector<double>{10, 20, 30, 40}));
  EXPECT_EQ(t.series.values[0], Complex(1.5e-6, -2.5e-7));
  EXPECT_EQ(t.series.values[3], Complex(4.5e-6, -5.5e-7));
  EXPECT_EQ(t.labels, "Freq Hz Real m/N Imag m/N");
  EXPECT_TRUE(any_contains(t.warnings, {"tap.frf", "1 line(s) at 0 Hz dropped"}));

  auto error_of = [](const std::string& bad) {
    try {
      parse_cutpro_frf(bad, "bad.frf");
    } catch (const InputError& e) {
      return std::string(e.what());
    }
    return std::string("no error");
  };
  EXPECT_TRUE(contains(error_of("10\t1\t2\n20\t1\n"), "bad.frf:2: 2 field(s), expected 3")) << error_of("10\t1\t2\n20\t1\n");
  EXPECT_TRUE(contains(error_of("10\t1\t2\n20\tx\t1\n"), "bad.frf:2: field 2 (real part [m/N]) is 'x'"));
  EXPECT_TRUE(contains(error_of("10\t1\t2\nabc\n"), "bad.frf:2: field 1 (frequency [Hz]) is 'abc'"));
  EXPECT_TRUE(contains(error_of("10\t1\t2\n10\t1\t2\n"), "bad.frf:2: frequency 10 Hz is not above 10 Hz on line 1"));
  EXPECT_TRUE(contains(error_of("10\t1\tnan\n"), "bad.frf:1: field 3"));
  EXPECT_TRUE(contains(error_of("-1\t1\t2\n"), "negative"));
  EXPECT_TRUE(contains(error_of("Freq Hz Real m/N Imag m/N\n"), "no data lines"));
  // Found by fuzz/fuzz_cutpro.cpp: a line of separators only (was undefined behaviour) is blank.
  EXPECT_TRUE(contains(error_of(","), "no data lines"));
  EXPECT_EQ(parse_cutpro_frf(",;\t\n10\t1\t2\n", "ok.frf").series.size(), 1u);
  // Any header but CutPro's is refused: the columns may be something else.
  EXPECT_TRUE(contains(error_of("header only\n"), "bad.frf:1: 'header only' is not CutPro's header"));
  EXPECT_TRUE(contains(error_of("Frequency [Hz]\tReal [m/N]\tImag [m/N]\n10\t1\t2\n"), "is not CutPro's header"));
  // Labels after the data are no header either.
  EXPECT_TRUE(contains(error_of("10\t1\t2\nFreq Hz Real m/N Imag m/N\n"), "bad.frf:2: field 1 (frequency [Hz]) is 'Freq'"));
}

TEST(FrfFile, CutProTextWrittenStrictly) {
  FrfSeries s;
  s.frequency_hz = {10.0, 12.5, 1e5};
  s.values = {{1.5e-6, -2.5e-7}, {0.1, 0.0}, {-1.0 / 3.0, 1e-300}};
  EXPECT_EQ(format_cutpro_frf(s), "10\t1.5e-06\t-2.5e-07\n12.5\t0.1\t0\n100000\t-0.3333333333333333\t1e-300\n");
  const FrfText back = parse_cutpro_frf(format_cutpro_frf(s), "rt.frf");
  EXPECT_EQ(back.series.frequency_hz, s.frequency_hz);
  EXPECT_EQ(back.series.values, s.values);  // shortest round-trip text: exact
}

// One entry point by extension, and writing in every format then reading back. CSV, .frf and
// binary UFF are exact; ASCII UFF writes this even grid exactly in record 7 and the values with
// 13 or more significant digits (5e-13).
TEST(FrfFile, ReadAndWriteEveryFormat) {
  TempDir dir;
  FrfSeries h = sdof_series(50, 10.0);
  for (const char* name : {"a.csv", "a.frf", "a.uff", "a.unv", "a.UF", "b.uff"}) {
    SCOPED_TRACE(name);
    const std::string path = dir / name;
    FrfWriteOptions w;
    if (std::string(name) == "b.uff") w.format = FrfFormat::UffBinary;
    w.dof = {3, 1, 4, -2};
    const auto lost = write_frf_file(path, h, w);
    EXPECT_TRUE(lost.empty());
    const FrfFileData r = read_frf_file(path);
    EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
    ASSERT_EQ(r.single.size(), h.size());
    const bool ascii_uff = r.format == FrfFormat::Uff && std::string(name) != "b.uff";
    for (std::size_t i = 0; i < h.size(); ++i) {
      ASSERT_EQ(r.single.frequency_hz[i], h.frequency_hz[i]);
      ASSERT_LE(std::abs(r.single.values[i] - h.values[i]), (ascii_uff ? 5e-13 : 0.0) * std::abs(h.values[i]));
    }
    if (r.format == FrfFormat::Uff) {
      EXPECT_EQ(r.dof.response_node, 3);
      EXPECT_EQ(r.dof.reference_direction, -2);
    }
  }
  // Uneven frequencies: ASCII UFF keeps 7 significant digits and says so; binary is exact.
  h.frequency_hz[7] = 80.123456789;
  EXPECT_TRUE(any_contains(write_frf_file(dir / "u.uff", h), {"abscissa", "7 significant digits", "58b"}));
  EXPECT_NEAR(read_frf_file(dir / "u.uff").single.frequency_hz[7], 80.123456789, 5e-7 * 80.12);
  EXPECT_TRUE(write_frf_file(dir / "u.unv", h, {.format = FrfFormat::UffBinary}).empty());
  EXPECT_EQ(read_frf_file(dir / "u.unv").single.frequency_hz[7], 80.123456789);

  // A block CSV comes back as a block; it can only be written as CSV.
  BlockSeries b;
  b.frequency_hz = {10.0, 20.0};
  b.blocks = {make_block(1e-6, 2, 3, 4), make_block(5e-6, 6, 7, 8)};  // H a plausible receptance [m/N]
  write_frf_csv(dir / "blk.csv", b);
  const FrfFileData rb = read_frf_file(dir / "blk.csv");
  EXPECT_TRUE(rb.is_block);
  EXPECT_EQ(rb.block.blocks[1](1, 0), Complex(7.0));
  EXPECT_THROW(write_frf_file(dir / "blk.frf", b), InvalidArgument);

  // Unknown extension, unless the format is named.
  write_text_file(dir / "tap.txt", "10\t1e-6\t2e-6\n");
  EXPECT_THROW(read_frf_file(dir / "tap.txt"), InvalidArgument);
  EXPECT_EQ(read_frf_file(dir / "tap.txt", {.format = FrfFormat::Frf}).single.size(), 1u);
  EXPECT_THROW(read_frf_file(dir / "tap.txt", {.format = FrfFormat::Frf, .uff = {.index = 0}}), InvalidArgument);
  EXPECT_THROW(read_frf_file(dir / "missing.csv"), IoError);
}

// A stray line — a point far beyond the measured band at either end (1e9 Hz after 10–5000 Hz in the
// new user's file) — is refused, naming the point and the median step; so is a top frequency no
// tool point measurement reaches (3e5 Hz: kTopFrequency's limit is 2e5), while 3e4 Hz (beyond the
// usual 2e4) is said. A measured band with a coarser part (two bands in one file) is read as it is.
TEST(FrfFile, StrayEndPointsAndImpossibleFrequenciesAreRefused) {
  TempDir dir;
  const auto write = [&](const std::string& name, const std::vector<double>& f) {
    FrfSeries s;
    for (double x : f) {
      s.frequency_hz.push_back(x);
      s.values.push_back(sdof_receptance(x));
    }
    write_frf_csv(dir / name, s);
    return dir / name;
  };
  std::vector<double> band;
  for (int i = 0; i <= 400; ++i) band.push_back(10.0 + 12.5 * i);
  std::vector<double> stray = band;
  stray.push_back(1e9);
  try {
    read_frf_file(write("stray.csv", stray));
    ADD_FAILURE() << "a stray point at 1e9 Hz was read";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "stray.csv: its last point, at 1e+09 Hz (point 402 of 402)")) << e.what();
    EXPECT_TRUE(contains(e.what(), "median step of 12.5 Hz")) << e.what();
    EXPECT_TRUE(contains(e.hint(), "remove that line")) << e.hint();
  }
  std::vector<double> first = band;
  first.insert(first.begin(), 0.001);
  first.erase(first.begin() + 1);  // 0.001 Hz, then 22.5 Hz: 1.8 steps, fine
  EXPECT_NO_THROW(read_frf_file(write("first.csv", first)));
  std::vector<double> two_bands = band;  // then 5 times coarser up to 10 kHz
  for (double f = band.back() + 62.5; f <= 10000.0; f += 62.5) two_bands.push_back(f);
  EXPECT_NO_THROW(read_frf_file(write("two.csv", two_bands)));
  std::vector<double> high;
  for (int i = 1; i <= 100; ++i) high.push_back(3000.0 * i);  // to 3e5 Hz
  EXPECT_THROW(read_frf_file(write("high.csv", high)), InputError);
  high.resize(10);  // to 3e4 Hz
  const FrfFileData r = read_frf_file(write("wide.csv", high));
  EXPECT_TRUE(any_contains(r.warnings, {"wide.csv: the top frequency [Hz] = 30000 is outside the usual range"}))
      << (r.warnings.empty() ? "" : r.warnings.front());
}

TEST(FrfFile, EvenGridDetection) {
  FrfSeries h;
  for (int i = 0; i < 5; ++i) {
    h.frequency_hz.push_back(0.5 + 0.25 * i);
    h.values.emplace_back(i, -i);
  }
  const UffDataset58 even = uff_from_receptance(h, {}, "grid");
  EXPECT_TRUE(even.even);
  EXPECT_EQ(even.abscissa_min, 0.5);
  EXPECT_EQ(even.abscissa_increment, 0.25);
  EXPECT_EQ(even.function_type, 4);
  EXPECT_EQ(even.ordinate.data_type, 8);
  EXPECT_EQ(even.denominator.data_type, 13);
  EXPECT_EQ(even.abscissa.data_type, 18);
  h.frequency_hz[0] = 0.4;
  EXPECT_FALSE(uff_from_receptance(h, {}, "grid").even);
  // A step that 7 digits cannot hold is written uneven, so binary keeps it exact.
  for (int i = 0; i < 5; ++i) h.frequency_hz[static_cast<std::size_t>(i)] = 1.0 + i / 3.0;
  EXPECT_FALSE(uff_from_receptance(h, {}, "grid").even);
}

// FrfWriteOptions::check names the field at fault, and write_frf_file refuses before writing: a
// comment with a line break would end the CSV comment and leave an unreadable data line; a
// coherence γ² outside [0, 1] (or NaN) cannot be a coherence. No file may be left behind.
TEST(FrfFile, WriteOptionsCheckNamesTheField) {
  TempDir dir;
  FrfSeries h = sdof_series(5, 100.0);
  const auto refused = [&](const FrfWriteOptions& w, const std::string& field) {
    SCOPED_TRACE(field);
    const std::string path = dir / "refused.csv";
    try {
      write_frf_file(path, h, w);
      ADD_FAILURE() << "accepted";
    } catch (const InvalidArgument& e) {
      EXPECT_TRUE(contains(e.what(), field)) << e.what();
    }
    EXPECT_FALSE(fs::exists(path));
  };
  FrfWriteOptions w;
  EXPECT_NO_THROW(w.check());
  w.description = "one\nline too many";
  refused(w, "FrfWriteOptions::description");
  w = {};
  w.comments = {"fine", "second\r\nline"};
  refused(w, "FrfWriteOptions::comments[1]");
  w = {};
  w.coherence = {0.5, 1.0, 0.0, 1.0000001, 0.9};
  refused(w, "FrfWriteOptions::coherence[3]");
  w.coherence = {0.5, 1.0, std::nan(""), 1.0, 0.9};
  refused(w, "FrfWriteOptions::coherence[2]");
  w.coherence = {0.5, 1.0, 0.0, 1.0, 0.9};  // the edges are valid
  EXPECT_NO_THROW(write_frf_file(dir / "ok.csv", h, w));
}

// FRF files as real programs write them (tests/data/variants/, README there): every variant read
// to the right numbers, checked against the closed-form single-DOF receptance the files were made
// from (by make_variants.py, in Python; computed again here), each damaged file to the right error
// and exit code, and a round trip CSV → UFF → CutPro → CSV → binary UFF → CSV keeping every point
// to 1e-12. Tolerances follow the digits each file prints (stated per file).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>

#include <fmt/format.h>

#include "toolpoint/error.hpp"
#include "toolpoint/frf_file.hpp"
#include "toolpoint/io.hpp"
#include "toolpoint/uff.hpp"
#include "support/scratch.hpp"

using namespace toolpoint;
namespace fs = std::filesystem;

using uff_test::any_contains;
using uff_test::contains;

namespace {

const std::string kDir = std::string(TOOLPOINT_TEST_DATA_DIR) + "/variants/";

// The oscillator of make_variants.py: m = 0.04 kg, fn = 1600 Hz, ζ = 0.02.
Complex sdof(double f) {
  const double m = 0.04, wn = 2.0 * std::numbers::pi * 1600.0, zeta = 0.02;
  const double k = m * wn * wn, c = 2.0 * zeta * std::sqrt(k * m), w = 2.0 * std::numbers::pi * f;
  return 1.0 / Complex(k - m * w * w, c * w);
}
double coherence(double f) { return 0.9 + 0.09 * std::sin(f / 300.0); }
const std::vector<double> kFrequencies = {1000, 1200, 1400, 1600, 1800, 2000, 2200};

// Every point against the closed form, |H − H_exact| ≤ tol·|H_exact|. Python (the file) and C++
// (here) evaluate the formula each with its own rounding; at the resonance k − mω² cancels, which
// amplifies that 1/(2ζ) = 25×, so no tolerance is below 1e-13, whatever the file's digits.
void expect_sdof(const FrfFileData& r, double tol) {
  tol = std::max(tol, 1e-13);
  ASSERT_FALSE(r.is_block);
  ASSERT_EQ(r.single.frequency_hz, kFrequencies);
  for (std::size_t i = 0; i < r.single.size(); ++i) {
    const Complex h = sdof(r.single.frequency_hz[i]);
    EXPECT_LE(std::abs(r.single.values[i] - h), tol * std::abs(h)) << "at " << r.single.frequency_hz[i] << " Hz";
  }
}

std::string error_of(const std::string& file, const FrfReadOptions& o = {}) {
  try {
    read_frf_file(kDir + file, o);
  } catch (const Error& e) {
    return std::string(e.what()) + " | fix: " + e.hint();
  }
  return "no error";
}

using test::TempDir;

int run_cli(const std::string& args, std::string* output = nullptr) { return test::run_toolpoint(args, output); }

}  // namespace

// CSV dialects. The files print 16 or 17 significant digits; magnitude/phase and dB add the
// rounding of cos/sin and 10^(x/20) (x ≈ −125 dB: ln10/20·|x| ≈ 15 ulp): 1e-13 covers all
// (the floor of expect_sdof).
TEST(FrfVariants, CsvDialectsReadToTheClosedForm) {
  {
    SCOPED_TRACE("German-locale spreadsheet: BOM, ';', decimal comma, quoted header with units, CRLF");
    const FrfFileData r = read_frf_file(kDir + "csv_de_locale_semicolon_decimal_comma.csv");
    expect_sdof(r, 1e-14);
    EXPECT_TRUE(r.warnings.empty()) << r.warnings.front();
    EXPECT_TRUE(r.coherence.empty());
  }
  {
    SCOPED_TRACE("tab-separated magnitude, phase in degrees and coherence, a 0 Hz line");
    const FrfFileData r = read_frf_file(kDir + "csv_tab_mag_phase_deg_coherence.csv");
    expect_sdof(r, 1e-13);
    ASSERT_EQ(r.coherence.size(), kFrequencies.size());
    for (std::size_t i = 0; i < kFrequencies.size(); ++i) EXPECT_EQ(r.coherence[i], coherence(kFrequencies[i]));
    EXPECT_TRUE(any_contains(r.warnings, {"1 line(s) at 0 Hz dropped", "line 2"}));
  }
  {
    SCOPED_TRACE("Bode export: dB re 1 m/N, phase in radians, 'Frequency/Hz'");
    expect_sdof(read_frf_file(kDir + "csv_bode_db_phase_rad.csv"), 1e-13);
  }
  {
    SCOPED_TRACE("mobility in mm/s/N by the header's units: H = Y/(iω) × 1e-3");
    const FrfFileData r = read_frf_file(kDir + "csv_mobility_mm_per_s.csv");
    expect_sdof(r, 1e-13);
    EXPECT_EQ(r.ordinate, FrfOrdinate::Mobility);
    EXPECT_TRUE(any_contains(r.warnings, {"'mm/s/N' converted to SI", "× 0.001"}));
  }
  {
    SCOPED_TRACE("accelerance in g/N: scaled by 9.80665, not just warned about");
    const FrfFileData r = read_frf_file(kDir + "csv_accelerance_g.csv");
    expect_sdof(r, 1e-13);
    EXPECT_EQ(r.ordinate, FrfOrdinate::Accelerance);
    EXPECT_EQ(r.units.to_si, 9.80665);
    EXPECT_EQ(r.coherence.size(), 7u);
  }
  {
    SCOPED_TRACE("numpy.savetxt with comments and an extra column, reported");
    const FrfFileData r = read_frf_file(kDir + "csv_numpy_extra_column.csv");
    expect_sdof(r, 1e-15);
    EXPECT_EQ(r.coherence.size(), 7u);
    EXPECT_TRUE(any_contains(r.warnings, {"not used: column 5 ('channel')"}));
  }
}

// What the header cannot say is an error naming the column and the option that settles it;
// with the option, the same file reads to the right numbers.
TEST(FrfVariants, AmbiguousCsvNamesTheColumnAndTheOption) {
  const std::string phase = error_of("csv_phase_without_unit.csv");
  EXPECT_TRUE(contains(phase, "csv_phase_without_unit.csv:1: column 3 ('Phase') gives no unit: degrees or radians?")) << phase;
  EXPECT_TRUE(contains(phase, "mag-phase-deg or mag-phase-rad")) << phase;
  expect_sdof(read_frf_file(kDir + "csv_phase_without_unit.csv", {.csv = {.format = FrfValueFormat::MagPhaseDeg}}), 1e-13);

  const std::string bare = error_of("csv_no_header.csv");
  EXPECT_TRUE(contains(bare, "csv_no_header.csv:1: no header line")) << bare;
  EXPECT_TRUE(contains(bare, "FrfCsvOptions::format")) << bare;
  expect_sdof(read_frf_file(kDir + "csv_no_header.csv", {.csv = {.format = FrfValueFormat::ReIm}}), 1e-15);

  // Columns by number or name; a contradiction between the header and the option is refused.
  expect_sdof(read_frf_file(kDir + "csv_numpy_extra_column.csv", {.csv = {.columns = {"1", "re", "IM", "coh"}}}), 1e-15);
  EXPECT_THROW(read_frf_file(kDir + "csv_numpy_extra_column.csv", {.csv = {.format = FrfValueFormat::MagPhaseDeg}}),
               InvalidArgument);
  EXPECT_TRUE(contains(error_of("csv_numpy_extra_column.csv", {.csv = {.columns = {"1", "2", "x"}}}),
                       "names 'x', which is no header cell"));
  // The user's units win over the header's, with a warning; units and ordinate must agree.
  const FrfFileData as_si = read_frf_file(kDir + "csv_mobility_mm_per_s.csv", {.units = parse_frf_units("m/s/N").value()});
  EXPECT_NEAR(std::abs(as_si.single.values[3]), 1000.0 * std::abs(sdof(1600.0)), 1e-12 * std::abs(sdof(1600.0)) * 1000.0);
  EXPECT_TRUE(any_contains(as_si.warnings, {"says the values are in 'mm/s/N'", "'m/s/N'", "are used"}));
  EXPECT_THROW(read_frf_file(kDir + "csv_mobility_mm_per_s.csv",
                             {.ordinate = FrfOrdinate::Receptance, .units = parse_frf_units("g/N").value()}),
               InvalidArgument);
}

TEST(FrfVariants, CsvDamageIsAnErrorWithTheLine) {
  TempDir dir;
  auto error_text = [&](const std::string& text) {
    write_text_file(dir / "d.csv", text);
    try {
      read_frf_file(dir / "d.csv");
    } catch (const InputError& e) {
      return std::string(e.what()) + " | fix: " + e.hint();
    }
    return std::string("no error");
  };
  EXPECT_TRUE(contains(error_text("f,re,im\n10,1,2\n20,1,2,3\n"), "d.csv:3: 4 cell(s) separated by ',', the header has 3"));
  EXPECT_TRUE(contains(error_text("f,re,im\n10,0.1,0.5\n20,0.1,0.5 ,\n"), "no error"));  // a trailing separator
  EXPECT_TRUE(contains(error_text("f,re,im\n10,1,5\n20,1,5,5\n"), "decimal comma"));
  EXPECT_TRUE(contains(error_text("f;re;im\n10;1.000,5;2\n"), "d.csv:2: '1.000,5' holds both '.' and ','"));
  EXPECT_TRUE(contains(error_text("f,mag,phase [deg]\n10,-1,2\n"), "d.csv:2: column 2 ('mag') is -1: a linear magnitude"));
  EXPECT_TRUE(contains(error_text("f,re,im,coherence\n10,1,2,1.5\n"), "d.csv:2: column 4 ('coherence') is 1.5"));
  EXPECT_TRUE(contains(error_text("f,re,im\n10,1,nan\n"), "d.csv:2: column 3 ('im') is nan, expected a finite number"));
  EXPECT_TRUE(contains(error_text("f,re,im\n20,1,2\n10,1,2\n"), "d.csv:3: frequency 10 Hz is not above"));
  EXPECT_TRUE(contains(error_text("time,value\n1,2\n"), "d.csv:1: no frequency column"));
  EXPECT_TRUE(contains(error_text("f,re,im,real\n1,2,3,4\n"), "are both the real part"));
  EXPECT_TRUE(contains(error_text("f,re,im [furlong/N]\n1,2,3\n"), "gives the units 'furlong/N'"));
  EXPECT_TRUE(contains(error_text("\xFF\xFE"
                                  "f"),
                       "UTF-16"));
  // A block file in other units than SI is refused; in SI units, with its units and a coherence, read.
  EXPECT_TRUE(contains(error_text("f,H_re [mm/N],H_im,L_re,L_im,N_re,N_im,P_re,P_im\n1,1,1,1,1,1,1,1,1\n"),
                       "column 2 (H_re) is in 'mm/N'"));
  write_text_file(dir / "b.csv",
                  "\xEF\xBB\xBF"
                  "Frequency [Hz];H_re [m/N];H_im;L_re [1/N];L_im;N_re;N_im;P_re;P_im;Coherence\r\n"
                  "10;1,5e-6;2e-6;3;4;5;6;7;8;0,5\r\n");
  const BlockSeries b = read_block_csv(dir / "b.csv");
  EXPECT_EQ(b.blocks.at(0)(0, 0), Complex(1.5e-6, 2e-6));
  EXPECT_EQ(read_frf_file(dir / "b.csv").coherence, std::vector<double>{0.5});
}

// CutPro: both label variants, on the first data line (the MATLAB writer's layout, 13 significant
// digits: 1e-12) or on a line of their own (17 digits, CRLF); a magnitude/phase table renamed .frf
// refused with or without its header.
TEST(FrfVariants, CutProLabelsAndRenamedTables) {
  expect_sdof(read_frf_file(kDir + "frf_cutpro_labels_on_first_line.frf"), 1e-12);
  expect_sdof(read_frf_file(kDir + "frf_cutpro_labels_own_line.frf"), 1e-15);
  const std::string named = error_of("frf_mag_phase_renamed.frf");
  EXPECT_TRUE(contains(named, "frf_mag_phase_renamed.frf:1: 'Frequency?Magnitude?Phase' is not CutPro's header")) << named;
  EXPECT_TRUE(contains(named, "FrfReadOptions::format = FrfFormat::Csv with FrfCsvOptions::format (e.g. mag-phase-deg)"))
      << named;
  const std::string bare = error_of("frf_mag_phase_renamed_no_header.frf");
  EXPECT_TRUE(contains(bare, "looks like magnitude and phase")) << bare;
  // Read as the CSV it is, it gives the receptance.
  expect_sdof(read_frf_file(kDir + "frf_mag_phase_renamed.frf",
                            {.format = FrfFormat::Csv, .csv = {.format = FrfValueFormat::MagPhaseDeg}}),
              1e-13);
}

// UFF variants. Binary: exact doubles (the formula's rounding: 1e-13). ASCII E20.12: 13
// significant digits, 1e-12. E13.6: 7 digits, 1e-6.
TEST(FrfVariants, UffVariantsReadToTheClosedForm) {
  {
    SCOPED_TRACE("pyuff 58b: byte count num_pts × 8 for complex double");
    const FrfFileData r = read_frf_file(kDir + "uff_pyuff_58b_half_byte_count.uff");
    expect_sdof(r, 1e-14);
    EXPECT_TRUE(any_contains(r.warnings, {"all 7 points were read", "pyuff writes num_pts × 8"})) << r.warnings.front();
  }
  {
    SCOPED_TRACE("CRLF line ends and a stray CRLF before and after the binary data");
    const FrfFileData r = read_frf_file(kDir + "uff_58b_crlf_around_binary.uff");
    expect_sdof(r, 1e-14);
    EXPECT_TRUE(any_contains(r.warnings, {"2 stray line-break byte(s) before the binary data"}));
    EXPECT_TRUE(any_contains(r.warnings, {"(a line break) between the end of the binary data"}));
  }
  expect_sdof(read_frf_file(kDir + "uff_fortran_d_exponents.uff"), 1e-12);
  expect_sdof(read_frf_file(kDir + "uff_run_together_fields.uff"), 1e-6);
  {
    SCOPED_TRACE("accelerance labelled g over N: scaled by 9.80665");
    const FrfFileData r = read_frf_file(kDir + "uff_accelerance_g_per_N.uff");
    expect_sdof(r, 1e-12);
    EXPECT_TRUE(any_contains(r.warnings, {"values in 'g/N' converted to SI", "× 9.80665"}));
  }
  {
    SCOPED_TRACE("a 90-character number field read exactly");
    const UffFile f = read_uff(kDir + "uff_long_numeric_field.uff");
    ASSERT_EQ(f.functions.size(), 1u);
    EXPECT_EQ(f.functions[0].y.at(0), Complex(1e-6, -1e-6));
  }
  {
    SCOPED_TRACE("a file cut in the middle of its last number: refused, naming the record");
    const std::string e = error_of("uff_truncated_mid_number.uff");
    EXPECT_TRUE(contains(e, "record 12 (data, from line 14) is cut off")) << e;
    EXPECT_TRUE(contains(e, "its last number may be cut short")) << e;
  }
  {
    SCOPED_TRACE("the abscissa of even spacing is min + i·Δ, never summed");
    std::string text =
        "    -1\n    58\nNONE\nNONE\nNONE\nNONE\nNONE\n"
        "    4         0    0         0 NONE               1   3 NONE               1   3\n"
        "         4      1001         1  0.00000E+00  1.00000E-01  0.00000E+00\n"
        "        18    0    0    0 Frequency            Hz\n"
        "         8    0    0    0 Response             m\n"
        "        13    0    0    0 Force                N\n"
        "         0    0    0    0 NONE                 NONE\n";
    for (int i = 0; i < 1001; ++i) text += "  1.000000000000E+00" + std::string(i % 4 == 3 ? "\n" : "");
    text += "\n    -1\n";
    const UffFile f = parse_uff(text, "even.uff");
    ASSERT_EQ(f.functions.at(0).size(), 1001u);
    double summed = 0.0;
    for (int i = 1; i <= 1000; ++i) summed += 0.1;
    EXPECT_EQ(f.functions[0].x[1000], 100.0);   // 1000 × 0.1 rounds to 100 exactly
    EXPECT_NE(f.functions[0].x[1000], summed);  // the running sum is 99.9999999999986
    for (int i = 0; i <= 1000; ++i) ASSERT_EQ(f.functions[0].x[static_cast<std::size_t>(i)], i * 0.1);
  }
}

// Through the command line: exit codes, and the copy of a file whose ID line is too long.
TEST(FrfVariants, CommandLineExitCodes) {
  TempDir dir;
  std::string out;
  EXPECT_EQ(run_cli("convert " + kDir + "uff_truncated_mid_number.uff " + dir / "x.csv", &out), 3) << out;
  EXPECT_TRUE(contains(out, "cut off")) << out;
  EXPECT_FALSE(fs::exists(dir / "x.csv"));
  EXPECT_EQ(run_cli("convert " + kDir + "frf_mag_phase_renamed.frf " + dir / "x.csv", &out), 3) << out;
  EXPECT_EQ(run_cli("convert " + kDir + "csv_phase_without_unit.csv " + dir / "x.csv", &out), 3) << out;
  EXPECT_TRUE(contains(out, "--format")) << out;
  EXPECT_EQ(run_cli("convert " + kDir + "csv_phase_without_unit.csv " + dir / "x.csv --format mag-phase-deg", &out), 0) << out;
  expect_sdof(read_frf_file(dir / "x.csv"), 1e-13);
  EXPECT_EQ(run_cli("convert " + kDir + "frf_mag_phase_renamed.frf " + dir / "y.csv --from csv --format mag-phase-deg", &out), 0)
      << out;
  expect_sdof(read_frf_file(dir / "y.csv"), 1e-13);
  // A 95-character ID line: copied, cut to 80 characters, with a warning (it used to be exit 2).
  EXPECT_EQ(run_cli("convert " + kDir + "uff_long_id_line.uff " + dir / "copy.uff", &out), 0) << out;
  EXPECT_TRUE(contains(out, "ID line 1 has 95 characters, its field holds 80")) << out;
  EXPECT_EQ(read_uff(dir / "copy.uff").functions.at(0).id[0], std::string(80, 'x'));
}

// CSV → ASCII UFF → CutPro → CSV → binary UFF → CSV, by `toolpoint convert`, keeps every point
// to 1e-12 (ASCII UFF's E20.12 holds 13 significant digits: 5e-13; the rest is exact), and the
// even grid exactly; the coherence survives the CSV steps and is reported lost in the others.
TEST(FrfVariants, RoundTripCsvUffCutProKeepsEveryPoint) {
  TempDir dir;
  FrfSeries h;
  std::vector<double> coh;
  for (int i = 1; i <= 200; ++i) {
    h.frequency_hz.push_back(12.5 * i);
    h.values.push_back(sdof(12.5 * i));
    coh.push_back(coherence(12.5 * i));
  }
  write_frf_csv(dir / "a.csv", h, {}, coh);
  std::string out;
  const char* chain[][2] = {
      {"a.csv", "b.uff"}, {"b.uff", "c.frf"}, {"c.frf", "d.csv"}, {"d.csv", "e.unv --to uffb"}, {"e.unv", "f.csv"}};
  for (const auto& step : chain) {
    ASSERT_EQ(run_cli("convert " + dir / step[0] + " " + dir / step[1], &out), 0) << step[0] << ": " << out;
    if (std::string(step[0]) == "a.csv") EXPECT_TRUE(contains(out, "coherence column is not written")) << out;
  }
  for (const char* name : {"b.uff", "c.frf", "d.csv", "e.unv", "f.csv"}) {
    SCOPED_TRACE(name);
    const FrfFileData r = read_frf_file(dir / name);
    ASSERT_EQ(r.single.frequency_hz, h.frequency_hz);
    for (std::size_t i = 0; i < h.size(); ++i)
      ASSERT_LE(std::abs(r.single.values[i] - h.values[i]), 1e-12 * std::abs(h.values[i])) << i;
  }
  // CSV to CSV keeps the coherence bit for bit.
  ASSERT_EQ(run_cli("convert " + dir / "a.csv " + dir / "g.csv", &out), 0) << out;
  EXPECT_EQ(read_frf_file(dir / "g.csv").coherence, coh);
}

// Every command that reads an FRF takes the same options, spelt the same: a magnitude/phase file
// whose phase has no unit is refused by each, naming --format, and read by each with it.
TEST(FrfVariants, EveryCommandTakesTheSameReadingOptions) {
  TempDir dir;
  const std::string in = dir / "mag_phase.csv";  // as csv_phase_without_unit.csv, on a finer grid (modes needs ≥ 8 points)
  std::string text = "Freq,Mag,Phase\n";
  for (int i = 0; i <= 60; ++i) {
    const double f = 1000.0 + 20.0 * i;
    text += fmt::format("{},{},{}\n", f, std::abs(sdof(f)), std::arg(sdof(f)) * 180.0 / std::numbers::pi);
  }
  write_text_file(in, text);
  const std::string commands[] = {
      "filter " + in + " " + dir / "f.csv --window 3 --order 1",
      "noise " + in + " " + dir / "n.csv --sigma 0.01",
      "modes " + in + " --max-modes 1",
      "lobes --frf " + in + " --teeth 2 --kt 6e8 --kr 0.3 --immersion 0.5 --milling down --rpm 5000:6000",
      "convert " + in + " " + dir / "c.csv",
      "rotational --h00 " + in + " --h10 " + in + " --spacing 0.01 --order 1 --assume-reciprocity --output " + dir / "r.csv",
  };
  for (const std::string& c : commands) {
    std::string out;
    EXPECT_EQ(run_cli(c, &out), 3) << c << "\n" << out;
    EXPECT_TRUE(contains(out, "gives no unit: degrees or radians?") && contains(out, "--format mag-phase-deg")) << c << "\n"
                                                                                                                << out;
    EXPECT_EQ(run_cli(c + " --format mag-phase-deg", &out), 0) << c << "\n" << out;
  }
  // identify and couple read blocks through the same reader and take the same options.
  for (const char* c : {"identify", "couple"}) {
    std::string out;
    EXPECT_EQ(run_cli(std::string(c) + " --help", &out), 0);
    for (const char* flag : {"--ordinate", "--units", "--format", "--columns"}) EXPECT_TRUE(contains(out, flag)) << c << flag;
  }
}

// A tap test as measurement software numbers it (nodes 101, 102, 103, direction +Y), with a second
// direction measured too: `rotational --uff` needs --nodes (the message lists the nodes present)
// and --direction (two datasets per pair otherwise), and then gives exactly the block of the same
// test numbered 1, 2, 3. A dataset lost to a damaged byte count is not replaced by reciprocity.
TEST(FrfVariants, RotationalNodeMappingAndDirection) {
  TempDir dir;
  const std::string example = std::string(TOOLPOINT_SOURCE_DIR) + "/examples/bt40_shrinkfit_16mm.toml";
  std::string out;
  ASSERT_EQ(run_cli("taptest " + example + " --at tool --spacing 0.01 --frequencies 500:3000:50 --binary --output " +
                        dir / "tap.uff",
                    &out),
            0)
      << out;
  ASSERT_EQ(run_cli("rotational --uff " + dir / "tap.uff" + " --spacing 0.01 --output " + dir / "ref.csv", &out), 0) << out;
  UffFile f = read_uff(dir / "tap.uff");
  std::vector<UffDataset58> renumbered;
  for (int copy = 0; copy < 2; ++copy)
    for (UffDataset58 d : f.functions) {
      d.response_node += 100;
      d.reference_node += 100;
      d.response_direction = d.reference_direction = copy == 0 ? 2 : 3;  // +Y, and a +Z copy
      if (copy == 1)
        for (auto& y : d.y) y *= 2.0;
      renumbered.push_back(d);
    }
  write_uff(dir / "testlab.uff", renumbered, {.binary = true});
  const std::string base = "rotational --uff " + dir / "testlab.uff" + " --spacing 0.01 --output " + dir / "out.csv";
  EXPECT_EQ(run_cli(base, &out), 3);
  EXPECT_TRUE(contains(out, "no dataset with response and reference node 1 (the tip: the first of --nodes 1,2,3)")) << out;
  EXPECT_TRUE(contains(out, "the file holds response/reference nodes 101/101 +Y, 102/101 +Y")) << out;
  EXPECT_TRUE(contains(out, "--nodes 101,102,103")) << out;
  EXPECT_EQ(run_cli(base + " --nodes 101,102,103", &out), 3);
  EXPECT_TRUE(contains(out, "both have response node 101 and reference node 101 (directions +Y/+Y and +Z/+Z)")) << out;
  EXPECT_EQ(run_cli(base + " --nodes 101,102,103 --direction +Y", &out), 0) << out;
  const BlockSeries a = read_block_csv(dir / "ref.csv"), b = read_block_csv(dir / "out.csv");
  ASSERT_EQ(a.size(), b.size());
  for (std::size_t i = 0; i < a.size(); ++i) EXPECT_EQ(a.blocks[i], b.blocks[i]);
  EXPECT_EQ(run_cli(base + " --nodes 101,102,101", &out), 2);
  EXPECT_EQ(run_cli("rotational --h00 " + dir / "ref.csv --nodes 1,2,3 --spacing 0.01 --output " + dir / "x.csv", &out), 2);

  // Damage the byte count of the dataset H10 (response 2, reference 1) beyond repair: it is
  // skipped with a warning, and the block is refused rather than built from H01 by reciprocity.
  std::string bytes = read_text_file(dir / "tap.uff");
  const std::size_t second = bytes.find("    58b", bytes.find("    58b") + 1);
  ASSERT_NE(second, std::string::npos);
  const std::size_t rec6 = [&] {
    std::size_t at = second;
    for (int k = 0; k < 6; ++k) at = bytes.find('\n', at) + 1;
    return at;
  }();
  bytes.replace(rec6, 5, "    x");  // record 6 function type unreadable: the dataset is skipped
  write_text_file(dir / "damaged.uff", bytes);
  EXPECT_EQ(run_cli("rotational --uff " + dir / "damaged.uff" + " --spacing 0.01 --output " + dir / "d.csv", &out), 3);
  EXPECT_TRUE(contains(out, "1 dataset(s) 58 could not be read")) << out;
  EXPECT_TRUE(contains(out, "is not given, and N needs it")) << out;
  EXPECT_FALSE(fs::exists(dir / "d.csv"));
}

// The case: accelerance in g read as receptance gave negative modal masses. Read with its
// units, an accelerometer file in g/N gives the oscillator's own modal mass, 0.04 kg, through
// `modes` (the fit of noise-free data: 1 %), and FrfFileData says what the values were.
TEST(FrfVariants, AccelerometerFileInGGivesTheModalMass) {
  TempDir dir;
  std::string text = "Frequency (Hz),Real (g/N),Imag (g/N)\n";
  for (int i = 0; i <= 80; ++i) {
    const double f = 1200.0 + 10.0 * i, w = 2.0 * std::numbers::pi * f;
    const Complex a = -w * w * sdof(f) / 9.80665;
    text += fmt::format("{},{},{}\n", f, a.real(), a.imag());
  }
  write_text_file(dir / "acc.csv", text);
  const FrfFileData r = read_frf_file(dir / "acc.csv");
  EXPECT_EQ(r.units.label, "g/N");
  EXPECT_EQ(r.ordinate, FrfOrdinate::Accelerance);
  std::string out;
  ASSERT_EQ(run_cli("modes " + dir / "acc.csv --max-modes 1 --json", &out), 0) << out;
  const std::size_t at = out.find("\"mass_kg\": ");
  ASSERT_NE(at, std::string::npos) << out;
  EXPECT_NEAR(std::stod(out.substr(at + 11)), 0.04, 0.0004) << out;
}

// Fuzz findings of the issue. A file of many empty datasets: the listing is linear (measured by
// the benchmark list_empty_datasets) and its messages, and the error of a conversion, are capped
// (the first few, then a count: it printed 33 MB before). A number field of 83 characters that is
// exactly 1 (it was cut to 71 characters and read as 0).
TEST(FrfVariants, FuzzFindingsCappedMessagesAndLongNumbers) {
  TempDir dir;
  std::string empty;
  for (int i = 0; i < 20000; ++i) empty += "    -1\n    58\n    -1\n";
  write_text_file(dir / "empty.uff", empty);
  std::string out;
  EXPECT_EQ(run_cli("convert " + dir / "empty.uff --list", &out), 0) << out.substr(0, 2000);
  EXPECT_LT(out.size(), 4000u);
  EXPECT_TRUE(contains(out, "0 dataset(s) 58")) << out;
  EXPECT_TRUE(contains(out, "… and 19990 more datasets 58 skipped (all of them: --list --json)")) << out;
  EXPECT_EQ(run_cli("convert " + dir / "empty.uff " + dir / "x.csv", &out), 3);
  EXPECT_LT(out.size(), 2000u);
  EXPECT_TRUE(contains(out, "0 dataset(s) of other types, 20000 dataset(s) 58 unreadable")) << out;
  EXPECT_TRUE(contains(out, "… and 19995 more")) << out;

  const std::string one = "0." + std::string(80, '0') + "1E+81";  // 83 characters, exactly 1
  const std::string text =
      "    -1\n    58\nNONE\nNONE\nNONE\nNONE\nNONE\n"
      "    4         0    0         0 NONE               1   3 NONE               1   3\n"
      "         4         1         1  1.00000E+01  1.00000E+00  0.00000E+00\n"
      "        18    0    0    0 Frequency            Hz\n"
      "         8    0    0    0 Response             m\n"
      "        13    0    0    0 Force                N\n"
      "         0    0    0    0 NONE                 NONE\n" +
      one + "\n    -1\n";
  const UffFile f = parse_uff(text, "long.uff");
  ASSERT_EQ(f.functions.size(), 1u) << (f.skipped.empty() ? "" : f.skipped[0]);
  EXPECT_EQ(f.functions[0].y.at(0), Complex(1.0, 0.0));
}

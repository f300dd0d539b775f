// FRF files as real programs write them (tests/data/variants/, README there): every variant read
// to the right numbers, checked against the closed-form single-DOF receptance the files were made
// from (by make_variants.py, in Python; computed again here; support/variants.hpp), each damaged
// file to the right error. Tolerances follow the digits each file prints (stated per file). The
// exit codes and the round trip through every format are tested through the CLI
// (cli_files_test.cpp).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <numbers>

#include <fmt/format.h>

#include "toolpoint/error.hpp"
#include "toolpoint/io/frf_file.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/io/uff.hpp"
#include "support/scratch.hpp"
#include "support/variants.hpp"

using namespace toolpoint;
namespace fs = std::filesystem;

using uff_test::any_contains;
using uff_test::contains;

namespace {

const std::string& kDir = test::kVariantsDir;
using test::coherence;
using test::expect_sdof;
using test::sdof;
const std::vector<double>& kFrequencies = test::kVariantFrequencies;

// The error (and its fix) of reading `path`, or "no error".
std::string error_reading(const std::string& path, const FrfReadOptions& o = {}) {
  try {
    read_frf_file(path, o);
  } catch (const Error& e) {
    return std::string(e.what()) + " | fix: " + e.hint();
  }
  return "no error";
}
std::string error_of(const std::string& file, const FrfReadOptions& o = {}) { return error_reading(kDir + file, o); }

using test::TempDir;

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

// A vendor export with text above its header (title, date, channel: here with ';' and decimal
// commas, so the preamble splits differently from the table) reads to the closed form, with a
// warning naming the lines skipped; lines above a header that does not split like the data, or a
// table without a header, are not skipped (the reader's errors stand, as before).
TEST(FrfVariants, AVendorPreambleIsSkippedAndSaid) {
  TempDir dir;
  std::string text =
      "Exported by Analyzer 3.2, project 7\nDate: 2024-05-01; 12:00\nChannel: 1 (tool tip Y)\n"
      "\"Frequency [Hz]\";\"Real [m/N]\";\"Imag [m/N]\"\n";
  for (double f : kFrequencies) {
    const std::string line = fmt::format("{:.17g};{:.17g};{:.17g}\n", f, sdof(f).real(), sdof(f).imag());
    std::string comma = line;
    std::replace(comma.begin(), comma.end(), '.', ',');
    text += comma;
  }
  write_text_file(dir / "vendor.csv", text);
  const FrfFileData r = read_frf_file(dir / "vendor.csv");
  expect_sdof(r, 1e-15);
  EXPECT_TRUE(any_contains(r.warnings, {"vendor.csv: lines 1–3 above the header (line 4) skipped", "'Exported by Analyzer"}))
      << r.warnings.front();
  // No header under the preamble: nothing skipped, and the first line cannot be a header.
  write_text_file(dir / "bare.csv", "Exported by Analyzer\n1000,1e-7,2e-8\n1200,1e-7,2e-8\n");
  EXPECT_THROW(read_frf_file(dir / "bare.csv"), InputError);
}

// A phase column said to be in degrees whose values are radians (within ±π through a resonance,
// where a receptance's phase passes 90°) is refused at the header line, naming the column and the
// header to write; the same with FrfCsvOptions::format mag-phase-deg names the other format. The
// degrees file of the variants (phases to −176°) still reads.
TEST(FrfVariants, RadiansUnderADegreesHeaderAreRefused) {
  TempDir dir;
  std::string text = "Freq (Hz),Magnitude (m/N),Phase (deg)\n", bare = "Freq,Mag,Phase\n";
  for (double f : kFrequencies) {
    const std::string line = fmt::format("{:.17g},{:.17g},{:.17g}\n", f, std::abs(sdof(f)), std::arg(sdof(f)));
    text += line;
    bare += line;
  }
  write_text_file(dir / "rad.csv", text);
  const std::string e = error_reading(dir / "rad.csv");
  EXPECT_TRUE(contains(e, "rad.csv:1: column 3 ('Phase (deg)') is read in degrees, but every phase lies within ±π")) << e;
  EXPECT_TRUE(contains(e, "resonance at 1600 Hz")) << e;
  EXPECT_TRUE(contains(e, "'Phase (rad)'")) << e;
  write_text_file(dir / "bare.csv", bare);
  FrfReadOptions deg;
  deg.csv.format = FrfValueFormat::MagPhaseDeg;
  EXPECT_TRUE(contains(error_reading(dir / "bare.csv", deg), "mag-phase-rad")) << error_reading(dir / "bare.csv", deg);
  FrfReadOptions rad;
  rad.csv.format = FrfValueFormat::MagPhaseRad;
  expect_sdof(read_frf_file(dir / "bare.csv", rad), 1e-13);
  expect_sdof(read_frf_file(kDir + "csv_tab_mag_phase_deg_coherence.csv"), 1e-13);
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

// A fuzz finding: a number field of 83 characters that is exactly 1 (it was cut to 71 characters
// and read as 0). (The capped messages are tested through the CLI, cli_files_test.cpp.)
TEST(FrfVariants, FuzzFindingLongNumberField) {
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

// Tests of the UFF dataset 58/58b reader and writer. Independent references: what pyuff 2.5 reads
// from real files written by measurement and simulation software (tests/data/uff/
// pyuff_expected.json), the dataset 58 specification's fixed column layout (checked here by
// slicing columns, not by the reader), IEEE 754 bit patterns written by hand, and hand-made files
// exercising what real files get wrong.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <limits>
#include <nlohmann/json.hpp>
#include <random>
#include <sstream>

#include "toolpoint/error.hpp"
#include "toolpoint/io/uff.hpp"
#include "support/scratch.hpp"

using namespace toolpoint;

// Message checks (support/scratch.hpp).
using uff_test::any_contains;
using uff_test::contains;

namespace {

const std::string kDir = std::string(TOOLPOINT_TEST_DATA_DIR) + "/uff/";

// A dataset with reproducible values spanning many decades and both signs.
UffDataset58 synthetic(int ordinate_type, bool even, std::size_t n, unsigned seed) {
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> mant(-1.0, 1.0);
  std::uniform_int_distribution<int> expo(-12, 3);
  auto value = [&] { return mant(rng) * std::pow(10.0, expo(rng)); };
  UffDataset58 d;
  d.id[0] = "synthetic";
  d.ordinate_data_type = ordinate_type;
  d.even = even;
  d.response_node = 7;
  d.response_direction = -3;
  d.reference_node = 12;
  d.reference_direction = 1;
  d.abscissa = {18, 0, 0, 0, "Frequency", "Hz"};
  d.ordinate = {12, 0, 0, 0, "Acceleration", "m/s^2"};
  d.denominator = {13, 0, 0, 0, "Force", "N"};
  d.abscissa_min = even ? 2.5 : 0.0;
  d.abscissa_increment = even ? 0.25 : 0.0;
  double f = 1.0;
  for (std::size_t i = 0; i < n; ++i) {
    f += 0.1 + std::abs(mant(rng)) * 3.0;
    d.x.push_back(even ? 2.5 + static_cast<double>(i) * 0.25 : f);
    const bool cpx = ordinate_type == 5 || ordinate_type == 6;
    double re = value(), im = cpx ? value() : 0.0;
    if (ordinate_type == 2 || ordinate_type == 5) {  // single precision data hold float values
      const float re_f = static_cast<float>(re), im_f = static_cast<float>(im);
      re = re_f;
      im = im_f;
    }
    d.y.emplace_back(re, im);
  }
  return d;
}

double rel_diff(double a, double b) { return a == b ? 0.0 : std::abs(a - b) / std::max(std::abs(a), std::abs(b)); }

}  // namespace

// Every value pyuff reads from the real files. Abscissae are computed alike (min + i·increment)
// and ordinates parsed from the same digits or the same float bits, so first and last values must
// agree to the last bit (EXPECT_DOUBLE_EQ, 4 ulp). Sums differ only by summation order: pyuff's
// numpy pairwise sum errs by at most log2(n)·ε·Σ|y| ≈ 2e-15·Σ|y|; ours is in long double, so the
// tolerance is 1e-14·Σ|y|.
TEST(Uff, AgreesWithPyuffOnRealFiles) {
  std::ifstream in(kDir + "pyuff_expected.json");
  ASSERT_TRUE(in) << "missing " << kDir << "pyuff_expected.json";
  const nlohmann::json expected = nlohmann::json::parse(in);
  ASSERT_EQ(expected.size(), 9u);
  for (const auto& [name, want] : expected.items()) {
    SCOPED_TRACE(name);
    const UffFile f = read_uff(kDir + name);
    std::vector<int> types;
    for (const auto& d : f.datasets) types.push_back(d.type);
    EXPECT_EQ(types, want["set_types"].get<std::vector<int>>());
    EXPECT_TRUE(f.skipped.empty());
    ASSERT_EQ(f.functions.size(), want["datasets58"].size());
    for (const auto& w : want["datasets58"]) {
      const UffDataset58& d = f.functions.at(w["index"].get<std::size_t>());
      SCOPED_TRACE("dataset " + std::to_string(d.index));
      EXPECT_EQ(d.function_type, w["func_type"].get<int>());
      EXPECT_EQ(d.ordinate_data_type, w["ord_data_type"].get<int>());
      EXPECT_EQ(d.declared_points, w["num_pts"].get<long long>());
      ASSERT_EQ(d.size(), w["len"].get<std::size_t>());
      EXPECT_EQ(d.id[0], w["id1"].get<std::string>());
      EXPECT_EQ(d.response_node, w["rsp_node"].get<int>());
      EXPECT_EQ(d.response_direction, w["rsp_dir"].get<int>());
      EXPECT_EQ(d.reference_node, w["ref_node"].get<int>());
      EXPECT_EQ(d.reference_direction, w["ref_dir"].get<int>());
      EXPECT_DOUBLE_EQ(d.x.front(), w["x_first"].get<double>());
      EXPECT_DOUBLE_EQ(d.x.back(), w["x_last"].get<double>());
      long double sum_re = 0, sum_im = 0, sum_abs = 0;
      for (const Complex& y : d.y) {
        sum_re += y.real();
        sum_im += y.imag();
        sum_abs += std::abs(y.real()) + std::abs(y.imag());
      }
      const double tol = 1e-14 * static_cast<double>(sum_abs);
      if (d.is_complex()) {  // pyuff reports [re, im] pairs and separate sums
        EXPECT_DOUBLE_EQ(d.y.front().real(), w["data_first"][0].get<double>());
        EXPECT_DOUBLE_EQ(d.y.front().imag(), w["data_first"][1].get<double>());
        EXPECT_DOUBLE_EQ(d.y.back().real(), w["data_last"][0].get<double>());
        EXPECT_DOUBLE_EQ(d.y.back().imag(), w["data_last"][1].get<double>());
        EXPECT_NEAR(static_cast<double>(sum_re), w["sum_real"].get<double>(), tol);
        EXPECT_NEAR(static_cast<double>(sum_im), w["sum_imag"].get<double>(), tol);
      } else {
        EXPECT_DOUBLE_EQ(d.y.front().real(), w["data_first"].get<double>());
        EXPECT_DOUBLE_EQ(d.y.back().real(), w["data_last"].get<double>());
        EXPECT_NEAR(static_cast<double>(sum_re), w["sum"].get<double>(), tol);
        for (const Complex& y : d.y) ASSERT_EQ(y.imag(), 0.0);
      }
    }
  }
}

// The same record in ASCII (6 significant digits) and binary single precision: the values agree
// to the ASCII rounding, half a unit in the 6th digit (5e-6 relative).
TEST(Uff, AsciiAndBinaryCopiesOfOneRecordAgree) {
  const UffFile a = read_uff(kDir + "Sample_UFF58_ascii.uff"), b = read_uff(kDir + "Sample_UFF58b_bin.uff");
  ASSERT_EQ(a.functions.size(), 1u);
  ASSERT_EQ(b.functions.size(), 1u);
  EXPECT_TRUE(b.functions[0].binary);
  ASSERT_EQ(a.functions[0].size(), b.functions[0].size());
  for (std::size_t i = 0; i < a.functions[0].size(); ++i)
    ASSERT_NEAR(a.functions[0].y[i].real(), b.functions[0].y[i].real(), 5e-6 * std::abs(b.functions[0].y[i].real())) << i;
}

// The damaged files: what can be read is read, and the warnings say what is wrong and where.
TEST(Uff, DamagedFilesAreReadWithClearWarnings) {
  const UffFile m = read_uff(kDir + "dataset_milestone_in_header.uff");
  ASSERT_EQ(m.functions.size(), 1u);
  EXPECT_EQ(m.functions[0].size(), 42u);
  EXPECT_TRUE(any_contains(m.functions[0].warnings, {"dataset_milestone_in_header.uff", "record 7", "2508876", "42"}));
  EXPECT_EQ(m.warnings, m.functions[0].warnings);

  const UffFile w = read_uff(kDir + "mpstd_58b_wrong_byte_count.uff");
  ASSERT_EQ(w.functions.size(), 4u);
  for (const auto& d : w.functions) {
    EXPECT_EQ(d.size(), 222400u);
    ASSERT_EQ(d.warnings.size(), 1u);
    EXPECT_TRUE(any_contains(d.warnings, {"mpstd_58b_wrong_byte_count.uff", "58b", "2 byte(s)", "line break", "-1"}));
  }
  EXPECT_EQ(w.warnings.size(), 4u);
  EXPECT_TRUE(w.file_warnings.empty());
  EXPECT_EQ(w.warnings_for({&w.functions[2]}), w.functions[2].warnings);  // a caller of #2 hears about #2 only
  // The well-formed files read without a single warning.
  for (const char* name :
       {"Sample_UFF58_ascii.uff", "Sample_UFF58b_bin.uff", "binary8byte.uff", "non_ascii_header.uff", "sample_dataset58_psd.uff",
        "time-history-not-all-columns-filled.uff", "nx_simulation_mixed_datasets.uff"})
    EXPECT_TRUE(read_uff(kDir + name).warnings.empty()) << name;
}

// 182 datasets of other types, one holding a line that reads "58": no dataset 58 appears.
TEST(Uff, OtherDatasetTypesAreSkippedEvenWithA58Line) {
  std::ifstream in(kDir + "nx_simulation_mixed_datasets.uff");
  std::string line;
  bool has_58_line = false;
  while (std::getline(in, line)) {
    std::istringstream ss(line);
    std::string tok, more;
    if (ss >> tok && tok == "58" && !(ss >> more)) has_58_line = true;
  }
  ASSERT_TRUE(has_58_line) << "the test file no longer exercises a '58' line inside another dataset";
  const UffFile f = read_uff(kDir + "nx_simulation_mixed_datasets.uff");
  EXPECT_EQ(f.datasets.size(), 182u);
  EXPECT_TRUE(f.functions.empty());
  EXPECT_TRUE(f.skipped.empty());
  EXPECT_THROW(select_dataset58(f, {}), InputError);
}

namespace {

const char* kHeader58 =
    "NONE\nNONE\nNONE\nNONE\nNONE\n"
    "    4         0    0         0 NONE               1   3 NONE               2   1\n"
    "         6         2         1  1.00000E+01  5.00000E+00  0.00000E+00\n"
    "        18    0    0    0 Frequency            Hz\n"
    "        12    0    0    0 Acceleration         m/s2\n"
    "        13    0    0    0 Force                N\n"
    "         0    0    0    0 NONE                 NONE\n";

}  // namespace

// A dataset starts only on the line after a "    -1": a "    58" inside another dataset, and
// text between datasets, are not datasets.
TEST(Uff, ADatasetStartsOnlyAfterADelimiter) {
  const std::string text = std::string("    -1\n  2414\n    58\n") + kHeader58 + "    -1\nstray text\n    58\n    -1\n    58\n" +
                           kHeader58 + " 1.0E+00 2.0E+00 3.0E+00 4.0E+00\n    -1\n";
  const UffFile f = parse_uff(text, "t.uff");
  ASSERT_EQ(f.datasets.size(), 2u);
  EXPECT_EQ(f.datasets[0].type, 2414);
  EXPECT_EQ(f.datasets[1].type, 58);
  EXPECT_EQ(f.datasets[1].line, 18u);
  ASSERT_EQ(f.functions.size(), 1u);
  EXPECT_EQ(f.functions[0].y[1], Complex(3.0, 4.0));
  EXPECT_TRUE(any_contains(f.warnings, {"t.uff:16", "2 line(s) outside any dataset", "stray text"}));
}

// What files in the wild do: CRLF line ends, numbers run together in full fields, D exponents,
// Fortran's letterless three-digit exponents, tabs, Latin-1 labels, a free-format record 6,
// record 6 entity names with blanks.
TEST(Uff, LiberalReading) {
  const std::string text =
      "    -1\r\n    58\r\nID one\r\nNONE\r\nNONE\r\nNONE\r\nNONE\r\n"
      "4 0 0 0 PT 5 -2 REF 9 2\r\n"
      "         5         4         0  0.00000E+00  0.00000E+00  0.00000E+00\r\n"
      "        18    0    0    0 Frequency            Hz\r\n"
      "        12    0    0    0 Acc                  m/s\xB2\r\n"  // Latin-1 "²"
      "        13    0    0    0 Force                N\r\n"
      "         0    0    0    0 NONE                 NONE\r\n"
      " 1.00000E+01-1.50000E-02-2.50000D-02 2.0E+01\t3.0e0,4.0E+00\r\n"
      "3.0E+01 1.5-100 -2.5+002 4.0E+01 1.0E+00 2.0E+00\r\n";
  const UffFile f = parse_uff(text + "    -1\r\n", "wild.uff");
  ASSERT_EQ(f.functions.size(), 1u) << (f.skipped.empty() ? "" : f.skipped[0]);
  const UffDataset58& d = f.functions[0];
  EXPECT_EQ(d.response_entity, "PT");
  EXPECT_EQ(d.response_direction, -2);
  EXPECT_EQ(d.reference_node, 9);
  EXPECT_EQ(d.ordinate.units, "m/s\u00b2");
  ASSERT_EQ(d.size(), 4u);
  EXPECT_EQ(d.x, (std::vector<double>{10.0, 20.0, 30.0, 40.0}));
  EXPECT_EQ(d.y[0], Complex(-1.5e-2, -2.5e-2));
  EXPECT_EQ(d.y[1], Complex(3.0, 4.0));
  EXPECT_EQ(d.y[2], Complex(1.5e-100, -2.5e2));
  EXPECT_TRUE(f.warnings.empty()) << f.warnings.front();

  // Without its closing delimiter the record is cut off: its last number may be cut short
  // ("2.0E+00" of "2.0E+001"), so the dataset is refused, naming the record, not read.
  const UffFile cut = parse_uff(text, "cut.uff");
  EXPECT_TRUE(cut.functions.empty());
  EXPECT_TRUE(any_contains(cut.skipped, {"cut.uff:15", "record 12", "cut off", "12 of the 12 values"})) << cut.skipped.at(0);

  // Entity names with blanks need the fixed columns of record 6 (binary8byte.uff has " sine 5 Hz").
  const UffFile b = read_uff(kDir + "binary8byte.uff");
  EXPECT_EQ(b.functions.at(0).response_entity, "sine 5 Hz");
  EXPECT_EQ(b.functions.at(0).response_node, 1);
}

// Errors name the file, the line, the record and field, and what was expected; the dataset is
// skipped, the rest of the file read, and selecting the broken dataset reports why.
TEST(Uff, MalformedHeaderSkipsTheDatasetAndSaysWhy) {
  std::string bad = std::string("    -1\n    58\n") + kHeader58 + " 1.0 2.0 3.0 4.0\n    -1\n";
  bad.replace(bad.find("         6         2"), 20, "         7         2");
  const std::string good = std::string("    -1\n    58\n") + kHeader58 + " 1.0 2.0 3.0 4.0\n    -1\n";
  const UffFile f = parse_uff(bad + good, "broken.uff");
  ASSERT_EQ(f.skipped.size(), 1u);
  EXPECT_TRUE(any_contains(f.skipped, {"broken.uff:9", "record 7 field 1", "ordinate data type", "is 7", "expected 2"}));
  ASSERT_EQ(f.functions.size(), 1u);
  EXPECT_EQ(f.functions[0].index, 1u);
  EXPECT_TRUE(any_contains(f.warnings_for({&f.functions[0]}), {"1 dataset(s) 58 could not be read"}));
  try {
    select_dataset58(f, UffSelection{.index = 0});
    FAIL() << "selected a skipped dataset";
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "record 7 field 1")) << e.what();
  }

  std::string bad_number = good;
  bad_number.replace(bad_number.find(" 3.0"), 4, " 3.x");
  const UffFile g = parse_uff(bad_number, "num.uff");
  EXPECT_TRUE(any_contains(g.skipped, {"num.uff:14", "record 12", "column 12", "'x 4.0'", "not a number", "4E20.12"}))
      << (g.skipped.empty() ? "" : g.skipped[0]);

  std::string short_header = std::string("    -1\n    58\nNONE\nNONE\n    -1\n") + good;
  const UffFile h = parse_uff(short_header, "short.uff");
  EXPECT_TRUE(any_contains(h.skipped, {"short.uff:5", "record 3", "11 header lines"}));
  EXPECT_EQ(h.functions.size(), 1u);
}

// A binary header that lies about its size: the reader takes what the data up to the closing
// delimiter hold, allocates no more than that, and says so; without a closing delimiter the
// record is cut off and refused.
TEST(Uff, LyingBinaryCountsAreBoundedByTheBytesPresent) {
  std::string head = "    -1\n    58b     1     2          11 99999999999999     0     0           0           0\n";
  std::string recs = kHeader58;
  recs.replace(recs.find("         6         2"), 20, "         29999999999");
  std::string data(40, '\0');
  for (int i = 0; i < 10; ++i) {
    const float v = static_cast<float>(i) + 0.5f;
    std::memcpy(&data[static_cast<std::size_t>(4 * i)], &v, 4);
  }
  const UffFile f = parse_uff(head + recs + data + "    -1\n", "lying.uff");
  ASSERT_EQ(f.functions.size(), 1u) << (f.skipped.empty() ? "" : f.skipped[0]);
  const UffDataset58& d = f.functions[0];
  EXPECT_EQ(d.declared_points, 9999999999LL);
  ASSERT_EQ(d.size(), 10u);
  EXPECT_EQ(d.y[9].real(), 9.5);
  EXPECT_TRUE(any_contains(d.warnings, {"agree with neither count", "58b field 6: 99999999999999 bytes", "40 bytes"}));
  EXPECT_TRUE(any_contains(d.warnings, {"declares 9999999999 points", "holds 10"}));

  const UffFile cut = parse_uff(head + recs + data, "cut.uff");
  EXPECT_TRUE(cut.functions.empty());
  EXPECT_TRUE(any_contains(cut.skipped, {"cut.uff:", "record 12", "cut off", "40 bytes into the data"})) << cut.skipped.at(0);
}

// Byte order and float format against bit patterns written by hand: 1.5f is 3F C0 00 00, −2.0
// (double) is C0 00 00 00 00 00 00 00.
TEST(Uff, BinaryByteOrders) {
  auto file = [](int order, int type, const std::string& bytes) {
    std::string recs = kHeader58;
    recs.replace(recs.find("         6         2         1"), 30, "         " + std::to_string(type) + "         1         1");
    return "    -1\n    58b     " + std::to_string(order) + "     2          11" +
           std::string(12 - std::to_string(bytes.size()).size(), ' ') + std::to_string(bytes.size()) +
           "     0     0           0           0\n" + recs + bytes + "    -1\n";
  };
  const std::string f_be("\x3F\xC0\x00\x00", 4), f_le("\x00\x00\xC0\x3F", 4);
  const std::string d_be("\xC0\x00\x00\x00\x00\x00\x00\x00", 8), d_le("\x00\x00\x00\x00\x00\x00\x00\xC0", 8);
  EXPECT_EQ(parse_uff(file(2, 2, f_be), "be").functions.at(0).y.at(0).real(), 1.5);
  EXPECT_EQ(parse_uff(file(1, 2, f_le), "le").functions.at(0).y.at(0).real(), 1.5);
  EXPECT_EQ(parse_uff(file(2, 4, d_be), "be").functions.at(0).y.at(0).real(), -2.0);
  const UffFile le = parse_uff(file(1, 4, d_le), "le");
  EXPECT_EQ(le.functions.at(0).y.at(0).real(), -2.0);
  EXPECT_TRUE(le.warnings.empty());
  const UffFile vax = parse_uff(std::string(file(1, 4, d_le)).replace(25, 1, "1"), "vax.uff");
  EXPECT_TRUE(any_contains(vax.skipped, {"vax.uff:2", "floating-point format", "is 1", "IEEE 754"}));
}

// Write then read gives back the same data, for the 8 cases of the specification in ASCII and
// both binary byte orders. Binary: exact. ASCII: at least 6 (13-column) or 13 (20-column)
// significant digits are printed, so the relative error is below half a unit in the last digit:
// 5e-6 and 5e-13. Uneven abscissae sit in 13-column fields in ASCII (5e-6) and are exact in
// binary double (single: float rounding, 6e-8).
TEST(Uff, WriteThenReadRoundTrips) {
  for (int type : {2, 4, 5, 6}) {
    for (bool even : {true, false}) {
      for (int mode = 0; mode < 3; ++mode) {
        SCOPED_TRACE(::testing::Message() << "type " << type << (even ? " even" : " uneven") << " mode " << mode);
        const UffDataset58 a = synthetic(type, even, 37, static_cast<unsigned>(type * 10 + mode));
        UffWriteOptions o;
        o.binary = mode > 0;
        o.byte_order = mode == 2 ? 2 : 1;
        const UffText t = format_uff({a, a}, o);
        const UffFile f = parse_uff(t.bytes, "rt.uff");
        EXPECT_TRUE(f.warnings.empty()) << f.warnings.front();
        ASSERT_EQ(f.functions.size(), 2u);
        const UffDataset58& b = f.functions[1];
        EXPECT_EQ(b.binary, o.binary);
        EXPECT_EQ(b.ordinate_data_type, type);
        EXPECT_EQ(b.even, even);
        EXPECT_EQ(b.response_direction, -3);
        EXPECT_EQ(b.reference_node, 12);
        EXPECT_EQ(b.ordinate.units, "m/s^2");
        EXPECT_EQ(b.declared_points, 37);
        ASSERT_EQ(b.size(), a.size());
        const bool dbl = type == 4 || type == 6;
        const double y_tol = o.binary ? 0.0 : dbl ? 5e-13 : 5e-6;
        const double x_tol = even ? 0.0 : !o.binary ? 5e-6 : dbl ? 0.0 : 6e-8;
        for (std::size_t i = 0; i < a.size(); ++i) {
          ASSERT_LE(rel_diff(a.x[i], b.x[i]), x_tol) << i;
          ASSERT_LE(rel_diff(a.y[i].real(), b.y[i].real()), y_tol) << i;
          ASSERT_LE(rel_diff(a.y[i].imag(), b.y[i].imag()), y_tol) << i;
        }
        // Uneven abscissae that do not fit 7 digits are reported as rounded, except in binary double.
        EXPECT_EQ(t.warnings.empty(), even || (o.binary && dbl)) << (t.warnings.empty() ? "" : t.warnings[0]);
      }
    }
  }
}

// The written ASCII layout is the specification's, checked by slicing fixed columns (as pyuff and
// Fortran readers do) rather than with our reader: 6E13.5 / 4E20.12 / 2(E13.5,E20.12) /
// E13.5,2E20.12, records within 80 columns, record 6/7 integers in their columns.
TEST(Uff, WrittenAsciiFollowsTheFixedColumns) {
  struct Case {
    int type;
    bool even;
    std::vector<int> widths;  // fields of one line
  };
  const Case cases[] = {{2, true, {13, 13, 13, 13, 13, 13}}, {2, false, {13, 13, 13, 13, 13, 13}},
                        {5, true, {13, 13, 13, 13, 13, 13}}, {5, false, {13, 13, 13, 13, 13, 13}},
                        {4, true, {20, 20, 20, 20}},         {4, false, {13, 20, 13, 20}},
                        {6, true, {20, 20, 20, 20}},         {6, false, {13, 20, 20}}};
  for (const Case& c : cases) {
    SCOPED_TRACE(::testing::Message() << "type " << c.type << (c.even ? " even" : " uneven"));
    const UffDataset58 d = synthetic(c.type, c.even, 12, 99);
    const std::string text = format_uff({d}).bytes;
    std::vector<std::string> lines;
    std::istringstream ss(text);
    for (std::string l; std::getline(ss, l);) lines.push_back(l);
    for (const auto& l : lines) EXPECT_LE(l.size(), 80u) << l;
    EXPECT_EQ(lines[0], "    -1");
    EXPECT_EQ(lines[1], "    58");
    EXPECT_EQ(std::atoi(lines[7].substr(41, 10).c_str()), 7);      // record 6 field 6, response node: I10
    EXPECT_EQ(std::atoi(lines[7].substr(51, 4).c_str()), -3);      // field 7, response direction: I4
    EXPECT_EQ(std::atoi(lines[8].substr(0, 10).c_str()), c.type);  // record 7: 3I10
    EXPECT_EQ(std::atoi(lines[8].substr(10, 10).c_str()), 12);
    EXPECT_EQ(std::atoi(lines[8].substr(20, 10).c_str()), c.even ? 1 : 0);
    EXPECT_EQ(std::atoi(lines[10].substr(0, 10).c_str()), 12);    // record 9 data type: I10
    EXPECT_EQ(lines[10].substr(26, 20), "Acceleration        ");  // label: 1X,20A1 from column 27
    // Record 12 by columns, in the order the specification gives.
    std::vector<double> expected;
    for (std::size_t i = 0; i < d.size(); ++i) {
      if (!c.even) expected.push_back(d.x[i]);
      expected.push_back(d.y[i].real());
      if (c.type >= 5) expected.push_back(d.y[i].imag());
    }
    std::vector<double> got;
    for (std::size_t l = 13; l + 1 < lines.size(); ++l) {
      std::size_t col = 0;
      for (std::size_t k = 0; k < c.widths.size() && col < lines[l].size(); ++k) {
        const std::string field = lines[l].substr(col, static_cast<std::size_t>(c.widths[k]));
        ASSERT_EQ(field.size(), static_cast<std::size_t>(c.widths[k])) << lines[l];
        ASSERT_EQ(field[0], ' ') << "a field needs a leading blank: " << lines[l];
        got.push_back(std::strtod(field.c_str(), nullptr));
        col += static_cast<std::size_t>(c.widths[k]);
      }
    }
    EXPECT_EQ(lines.back(), "    -1");
    ASSERT_EQ(got.size(), expected.size());
    for (std::size_t i = 0; i < got.size(); ++i) EXPECT_LE(rel_diff(got[i], expected[i]), 5e-6) << i;
  }
}

// The 58b header line by its columns (I6,1A1,I6,I6,I12,I12,…) and the byte count against the
// bytes actually between the header and the closing delimiter.
TEST(Uff, WrittenBinaryHeaderAndByteCount) {
  const UffDataset58 d = synthetic(6, false, 25, 5);
  UffWriteOptions o;
  o.binary = true;
  o.byte_order = 2;
  const std::string bytes = format_uff({d}, o).bytes;
  const std::string head = bytes.substr(7, bytes.find('\n', 7) - 7);
  EXPECT_EQ(head.substr(0, 6), "    58");
  EXPECT_EQ(head[6], 'b');
  EXPECT_EQ(std::atoi(head.substr(7, 6).c_str()), 2);
  EXPECT_EQ(std::atoi(head.substr(13, 6).c_str()), 2);
  EXPECT_EQ(std::atoi(head.substr(19, 12).c_str()), 11);
  const long count = std::atol(head.substr(31, 12).c_str());
  EXPECT_EQ(count, 25 * 3 * 8);
  std::size_t start = 0;
  for (int l = 0; l < 13; ++l) start = bytes.find('\n', start) + 1;
  EXPECT_EQ(bytes.substr(start + static_cast<std::size_t>(count)), "    -1\n");
}

TEST(Uff, SelectionByIndexNodeAndDirection) {
  std::vector<UffDataset58> sets;
  const int nodes[][4] = {{1, 1, 1, 1}, {1, 2, 1, 1}, {2, 1, 1, 1}, {1, 1, 2, -3}};
  for (const auto& n : nodes) {
    UffDataset58 d = synthetic(6, true, 3, 1);
    d.response_node = n[0];
    d.response_direction = n[1];
    d.reference_node = n[2];
    d.reference_direction = n[3];
    sets.push_back(d);
  }
  const UffFile f = parse_uff(format_uff(sets).bytes, "sel.uff");
  ASSERT_EQ(f.functions.size(), 4u);
  auto pick = [&](UffSelection s) { return select_dataset58(f, s).index; };
  EXPECT_EQ(pick({.index = 2}), 2u);
  EXPECT_EQ(pick({.response_direction = 2}), 1u);
  EXPECT_EQ(pick({.response_node = 2}), 2u);
  EXPECT_EQ(pick({.reference_node = 2, .reference_direction = -3}), 3u);
  EXPECT_EQ(pick({.response_node = 1, .response_direction = 1, .reference_node = 1, .reference_direction = 1}), 0u);
  try {
    pick({.response_node = 1});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "3 datasets 58 match response node 1")) << e.what();
  }
  try {
    pick({.response_node = 5});
    FAIL();
  } catch (const InputError& e) {
    EXPECT_TRUE(contains(e.what(), "no dataset 58 matches response node 5")) << e.what();
    EXPECT_TRUE(contains(e.what(), "response 1 +Y")) << e.what();
  }
  EXPECT_THROW(pick({}), InputError);
  EXPECT_THROW(pick({.index = 4}), InputError);
}

// The writer refuses what the format cannot hold.
TEST(Uff, WriterRejectsWhatDoesNotFit) {
  UffDataset58 d = synthetic(4, true, 3, 2);
  d.y[1] = Complex(1.0, 2.0);
  EXPECT_THROW(format_uff({d}), InvalidArgument);  // imaginary part in real data
  d = synthetic(6, true, 3, 2);
  d.response_node = -1'000'000'000;  // 11 characters in a 10-column field
  EXPECT_THROW(format_uff({d}), InvalidArgument);
  d = synthetic(6, true, 3, 2);
  d.ordinate.label = "two\nlines";
  EXPECT_THROW(format_uff({d}), InvalidArgument);
  d = synthetic(6, true, 3, 2);
  d.x[2] = 99.0;  // not on the even grid
  EXPECT_THROW(format_uff({d}), InvalidArgument);
  d = synthetic(6, false, 3, 2);
  d.x.pop_back();
  EXPECT_THROW(format_uff({d}), InvalidArgument);
  EXPECT_THROW(format_uff({synthetic(6, true, 3, 2)}, UffWriteOptions{.binary = true, .byte_order = 3}), InvalidArgument);
}

// Text longer than its field (a 95-character ID line from another program's file, a long label)
// is cut to the field on write, with a warning naming the field, never refused: a copy must not
// fail on what the user cannot change (a fuzz finding of issue 12). The cut never splits a
// character, and the file reads back with the cut text in place.
TEST(Uff, LongTextIsCutOnWriteWithAWarning) {
  UffDataset58 d = synthetic(6, true, 3, 2);
  d.id[0] = std::string(90, 'a') + "µµµµµ";  // 95 characters
  d.ordinate.units = "m/s² per newton of force";
  d.response_entity = "a long entity";
  const UffText t = format_uff({d}, {.binary = true});
  ASSERT_EQ(t.warnings.size(), 3u);
  EXPECT_TRUE(any_contains(t.warnings, {"ID line 1 has 95 characters, its field holds 80"}));
  EXPECT_TRUE(any_contains(t.warnings, {"record 9 units label has 24 characters, its field holds 20", "'m/s² per newton of f'"}));
  EXPECT_TRUE(any_contains(t.warnings, {"response entity name has 13 characters, its field holds 10", "'a long ent'"}));
  const UffFile back = parse_uff(t.bytes, "cut.uff");
  ASSERT_EQ(back.functions.size(), 1u) << (back.skipped.empty() ? "" : back.skipped[0]);
  EXPECT_EQ(back.functions[0].id[0], std::string(80, 'a'));
  EXPECT_EQ(back.functions[0].ordinate.units, "m/s² per newton of f");
  EXPECT_EQ(back.functions[0].response_entity, "a long ent");
  EXPECT_EQ(back.functions[0].y, d.y);
}

// An ID line whose text is "-1" (a real file had it 23 columns in) must not be written where a
// reader takes it for the delimiter that ends the dataset (found by fuzz/fuzz_uff.cpp: the copy
// read back with no dataset).
TEST(Uff, AnIdLineReadingMinusOneIsNotWrittenAsADelimiter) {
  UffDataset58 d = synthetic(6, true, 3, 2);
  d.id[4] = "-1";
  d.id[1] = "  -1";
  for (bool binary : {false, true}) {
    const UffFile back = parse_uff(format_uff({d}, {.binary = binary}).bytes, "id.uff");
    ASSERT_EQ(back.functions.size(), 1u) << (back.skipped.empty() ? "" : back.skipped[0]);
    EXPECT_EQ(back.functions[0].id[4], "-1");
    EXPECT_EQ(back.functions[0].id[1], "-1");
    EXPECT_EQ(back.functions[0].size(), 3u);
  }
}

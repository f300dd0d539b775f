// The file commands through the command line — convert, resample, rotational from one UFF file,
// modes on a file in g/N, and the reading options every command shares: exit codes, messages and
// files, checked against the closed-form oscillator of tests/data/variants/ (support/variants.hpp)
// and the library's own readers. (Moved here from the library's tests so that those build without
// the CLI.)
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>

#include <fmt/format.h>

#include "toolpoint/io/frf_file.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/io/uff.hpp"
#include "support/scratch.hpp"
#include "support/variants.hpp"

using namespace toolpoint;
namespace fs = std::filesystem;

using test::coherence;
using test::expect_sdof;
using test::sdof;
using test::sdof_series;
using test::TempDir;
using uff_test::contains;

namespace {

const std::string& kDir = test::kVariantsDir;
const std::string kUffDir = std::string(TOOLPOINT_TEST_DATA_DIR) + "/uff/";

int run_cli(const std::string& args, std::string* output = nullptr) { return test::run_toolpoint(args, output); }

std::string slurp(const std::string& path) { return read_text_file(path); }

// `toolpoint ARGS`, its output kept in `out_file` for slurp().
int run_cli(const std::string& args, const std::string& out_file) {
  std::string out;
  const int code = test::run_toolpoint(args, &out);
  write_text_file(out_file, out);
  return code;
}

}  // namespace

// The command: listing, converting, and the exit codes of docs/files.md, "Exit codes".
TEST(FrfFile, ConvertCommand) {
  TempDir dir;
  const std::string log = dir / "log.txt";
  EXPECT_EQ(run_cli("convert " + kUffDir + "mpstd_58b_wrong_byte_count.uff --list", log), 0);
  const std::string listing = slurp(log);
  EXPECT_TRUE(contains(listing, "4 dataset(s) 58")) << listing;
  EXPECT_TRUE(contains(listing, "MPS set1 Dof3")) << listing;
  EXPECT_TRUE(contains(listing, "line break")) << listing;
  EXPECT_EQ(run_cli("convert " + kUffDir + "dataset_milestone_in_header.uff --list --json", log), 0);
  EXPECT_TRUE(contains(slurp(log), "\"declared_points\": 2508876")) << slurp(log);

  const std::string in = kUffDir + "non_ascii_header.uff";
  EXPECT_EQ(run_cli("convert " + in + " " + dir / "h.csv", log), 0) << slurp(log);  // the units label says accelerance
  EXPECT_TRUE(contains(slurp(log), "say accelerance, taken as such")) << slurp(log);
  EXPECT_EQ(run_cli("convert " + in + " " + dir / "h.csv --ordinate accelerance", log), 0) << slurp(log);
  EXPECT_TRUE(contains(slurp(log), "0 Hz dropped")) << slurp(log);
  const FrfSeries csv = read_single_csv(dir / "h.csv");
  EXPECT_EQ(csv.size(), 5u);

  // CSV → binary UFF → .frf keeps every bit; node/direction options label the UFF dataset.
  EXPECT_EQ(run_cli("convert " + dir / "h.csv " + dir / "h.unv --to uffb --response-node 4 --response-dir Y-", log), 0)
      << slurp(log);
  EXPECT_EQ(run_cli("convert " + dir / "h.unv " + dir / "h.frf --response-dir=-Y", log), 0) << slurp(log);
  const FrfFileData back = read_frf_file(dir / "h.frf");
  EXPECT_EQ(back.single.frequency_hz, csv.frequency_hz);
  EXPECT_EQ(back.single.values, csv.values);

  // UFF to UFF copies every dataset 58, binary to ASCII here.
  EXPECT_EQ(run_cli("convert " + kUffDir + "binary8byte.uff " + dir / "copy.uff", log), 0) << slurp(log);
  const UffFile copy = read_uff(dir / "copy.uff");
  ASSERT_EQ(copy.functions.size(), 1u);
  EXPECT_FALSE(copy.functions[0].binary);
  EXPECT_EQ(copy.functions[0].size(), 250u);
  EXPECT_EQ(copy.functions[0].response_entity, "sine 5 Hz");

  EXPECT_EQ(run_cli("convert " + in + " " + dir / "x.csv --dataset 0 --response-node 1", log), 2);  // exclusive
  EXPECT_EQ(run_cli("convert " + in + " " + dir / "x.xyz --ordinate accelerance", log), 2);         // unknown extension
  EXPECT_EQ(run_cli("convert " + in, log), 2);                                                      // no OUT
  EXPECT_EQ(run_cli("convert " + dir / "nothing.uff " + dir / "x.csv", log), 5);                    // cannot read
  EXPECT_EQ(run_cli("convert " + in + " " + dir / "x.csv --dataset 3 --ordinate accelerance", log), 3);
  EXPECT_TRUE(contains(slurp(log), "no dataset 58 matches dataset 3")) << slurp(log);
  EXPECT_FALSE(fs::exists(dir / "x.csv"));
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
  // The file cut off inside the fifth dataset (H11, order 1 needs it for P): P is not approximated
  // as if the hammer had stayed at the tip; asked for, it is.
  const std::size_t fifth = [&] {
    std::size_t at = 0;
    for (int k = 0; k < 5; ++k) at = bytes.find("    58b", at + 1);
    return at;
  }();
  write_text_file(dir / "cut.uff", read_text_file(dir / "tap.uff").substr(0, fifth + 400));
  const std::string cut = "rotational --uff " + dir / "cut.uff" + " --spacing 0.01 --order 1 --output " + dir / "c.csv";
  EXPECT_EQ(run_cli(cut, &out), 3) << out;
  EXPECT_TRUE(contains(out, "needs H11, not given, and the source could not read one part")) << out;
  EXPECT_TRUE(contains(out, "--p-method n2h")) << out;
  EXPECT_FALSE(fs::exists(dir / "c.csv"));
  EXPECT_EQ(run_cli(cut + " --p-method n2h", &out), 0) << out;
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

// A fuzz finding of the issue: a file of many empty datasets. The listing is linear (measured by
// the benchmark list_empty_datasets) and its messages, and the error of a conversion, are capped
// (the first few, then a count: it printed 33 MB before).
TEST(FrfVariants, FuzzFindingsCappedMessages) {
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
}

TEST(Resample, CommandLine) {
  const test::TempDir dir("toolpoint_resample");
  const auto p = [&](const char* leaf) { return dir / leaf; };
  write_frf_csv(p("fine.csv"), sdof_series(1000, 2000, 2.5), {}, std::vector<double>(401, 0.95));
  write_frf_csv(p("coarse.csv"), sdof_series(1200, 1800, 10));
  std::string out;
  ASSERT_EQ(run_cli("resample " + p("fine.csv") + " " + p("on.csv") + " --onto " + p("coarse.csv") + " --method cubic", &out), 0)
      << out;
  const FrfFileData on = read_frf_file(p("on.csv"));
  ASSERT_EQ(on.single.frequency_hz, sdof_series(1200, 1800, 10).frequency_hz);
  for (std::size_t i = 0; i < on.single.size(); ++i) EXPECT_EQ(on.single.values[i], sdof(on.single.frequency_hz[i]));
  EXPECT_EQ(on.coherence, std::vector<double>(61, 0.95));
  ASSERT_EQ(run_cli("resample " + p("fine.csv") + " " + p("band.uff") + " --band 1500:1600", &out), 0) << out;
  EXPECT_EQ(read_frf_file(p("band.uff")).single.size(), 41u);
  ASSERT_EQ(run_cli("resample " + p("coarse.csv") + " " + p("grid.frf") + " --grid 1200:1800:1", &out), 0) << out;
  EXPECT_EQ(read_frf_file(p("grid.frf")).single.size(), 601u);
  // Outside the measured range: exit 3, the fix names --band; with it, the target is cropped.
  EXPECT_EQ(run_cli("resample " + p("coarse.csv") + " " + p("x.csv") + " --onto " + p("fine.csv"), &out), 3);
  EXPECT_NE(out.find("target frequency 1000 Hz lies outside the measured range 1200–1800 Hz"), std::string::npos) << out;
  EXPECT_NE(out.find("--band"), std::string::npos) << out;
  EXPECT_FALSE(fs::exists(p("x.csv")));
  EXPECT_EQ(run_cli("resample " + p("coarse.csv") + " " + p("x.csv") + " --onto " + p("fine.csv") + " --band 1200:1800", &out), 0)
      << out;
  EXPECT_EQ(read_frf_file(p("x.csv")).single.size(), 241u);
  EXPECT_EQ(run_cli("resample " + p("coarse.csv") + " " + p("y.csv"), &out), 2);
  EXPECT_EQ(run_cli("resample " + p("coarse.csv") + " " + p("y.csv") + " --grid 1:2:1 --onto " + p("fine.csv"), &out), 2);
  EXPECT_EQ(run_cli("resample " + p("coarse.csv") + " " + p("y.csv") + " --band 1300:1400 --method quadratic", &out), 2);
  // The grid-mismatch error of another command points here.
  write_text_file(p("b1.csv"),
                  "frequency_hz,H_re,H_im,L_re,L_im,N_re,N_im,P_re,P_im\n10,1,0,1,0,1,0,1,0\n20,1,0,1,0,1,0,1,0\n"
                  "30,1,0,1,0,1,0,1,0\n");
  write_text_file(p("b2.csv"),
                  "frequency_hz,H_re,H_im,L_re,L_im,N_re,N_im,P_re,P_im\n10,1,0,1,0,1,0,1,0\n25,1,0,1,0,1,0,1,0\n"
                  "30,1,0,1,0,1,0,1,0\n");
  EXPECT_EQ(run_cli("identify --joint holder-tool --assembly " + std::string(TOOLPOINT_SOURCE_DIR) +
                        "/examples/bt40_shrinkfit_16mm.toml --sh " + p("b1.csv") + " --sht " + p("b2.csv"),
                    &out),
            3);
  EXPECT_NE(out.find("toolpoint resample IN OUT --onto OTHER"), std::string::npos) << out;
}

// Robustness of the FRF file parsers: thousands of mutated and truncated real files, written
// files of every layout, and random bytes, from a fixed seed. parse_uff must not throw at all;
// what comes after it (selection, conversion) and the .frf parser may throw InputError only.
// Nothing read may exceed what the input bytes can hold (a lying header must not make the reader
// allocate or invent data), and what is read must be consistent.
#include <gtest/gtest.h>

#include <fstream>
#include <random>
#include <sstream>
#include <typeinfo>

#include "toolpoint/error.hpp"
#include "toolpoint/io/frf_file.hpp"
#include "toolpoint/io/uff.hpp"

using namespace toolpoint;

namespace {

std::string file_head(const std::string& name, std::size_t max_bytes) {
  std::ifstream in(std::string(TOOLPOINT_TEST_DATA_DIR) + "/uff/" + name, std::ios::binary);
  std::string s(max_bytes, '\0');
  in.read(s.data(), static_cast<std::streamsize>(max_bytes));
  s.resize(static_cast<std::size_t>(in.gcount()));
  return s;
}

// Seeds: the real files (the large ones cut to their first 12 kB: header plus some data) and one
// written file of every layout, ASCII and binary.
std::vector<std::string> uff_seeds() {
  std::vector<std::string> seeds;
  for (const char* name :
       {"Sample_UFF58_ascii.uff", "Sample_UFF58b_bin.uff", "binary8byte.uff", "dataset_milestone_in_header.uff",
        "mpstd_58b_wrong_byte_count.uff", "non_ascii_header.uff", "nx_simulation_mixed_datasets.uff", "sample_dataset58_psd.uff",
        "time-history-not-all-columns-filled.uff"})
    seeds.push_back(file_head(name, 12000));
  for (int type : {2, 4, 5, 6})
    for (bool even : {true, false})
      for (bool binary : {false, true}) {
        UffDataset58 d;
        d.ordinate_data_type = type;
        d.even = even;
        d.abscissa_min = even ? 1.0 : 0.0;
        d.abscissa_increment = even ? 1.0 : 0.0;
        for (int i = 0; i < 9; ++i) {
          d.x.push_back(1.0 + i);
          d.y.emplace_back(0.5 * i - 1.0, type >= 5 ? 0.25 * i : 0.0);
        }
        seeds.push_back(format_uff({d, d}, {.binary = binary, .byte_order = binary && even ? 2 : 1}).bytes);
      }
  return seeds;
}

const char* const kInserts[] = {"    -1\n",
                                "    58\n",
                                "    58b     1     2          11  999999999999     0\n",
                                "    58b     2     2          11           8\n",
                                "\r\n",
                                "   164\n",
                                "         6 999999999         1  0.0E+00  1.0E+00\n",
                                "-1.0E+999",
                                "nan ",
                                "\xB2",
                                "\xC3\x28"};

std::string mutate(std::string s, std::mt19937& rng) {
  auto pick = [&](std::size_t n) { return n == 0 ? 0 : std::uniform_int_distribution<std::size_t>(0, n - 1)(rng); };
  const std::size_t rounds = 1 + pick(4);
  for (std::size_t r = 0; r < rounds; ++r) {
    const std::size_t at = pick(s.size() + 1);
    switch (pick(8)) {
      case 0:  // one byte anything
        if (!s.empty()) s[pick(s.size())] = static_cast<char>(pick(256));
        break;
      case 1:  // insert random bytes
        for (std::size_t k = 1 + pick(8); k > 0; --k)
          s.insert(s.begin() + static_cast<std::ptrdiff_t>(at), static_cast<char>(pick(256)));
        break;
      case 2:  // delete a range
        s.erase(at, 1 + pick(64));
        break;
      case 3:  // truncate
        s.resize(at);
        break;
      case 4: {  // duplicate a range
        const std::string piece = s.substr(at, 1 + pick(200));
        s.insert(pick(s.size() + 1), piece);
        break;
      }
      case 5: {  // a structural line at a line start
        const std::size_t nl = s.rfind('\n', at == 0 ? 0 : at - 1);
        s.insert(nl == std::string::npos ? 0 : nl + 1, kInserts[pick(std::size(kInserts))]);
        break;
      }
      case 6:  // a digit becomes another digit or a sign, exponent or blank
        for (std::size_t k = 0; k < 32 && !s.empty(); ++k) {
          const std::size_t i = pick(s.size());
          if (s[i] >= '0' && s[i] <= '9') {
            s[i] = "0123456789-+E. "[pick(15)];
            break;
          }
        }
        break;
      default:  // overwrite a span with random bytes
        for (std::size_t k = 0, n = pick(16); k < n && at + k < s.size(); ++k) s[at + k] = static_cast<char>(pick(256));
    }
  }
  return s;
}

// Everything a caller does with a parsed file; returns a description of the first broken rule.
std::string exercise(const std::string& bytes) {
  UffFile f;
  try {
    f = parse_uff(bytes, "fuzz.uff");
  } catch (const std::exception& e) {
    return std::string("parse_uff threw ") + typeid(e).name() + ": " + e.what();
  }
  for (const UffDataset58& d : f.functions) {
    if (d.x.size() != d.y.size()) return "x and y differ in length";
    if (static_cast<long long>(d.size()) > d.declared_points) return "more points than declared";
    if (d.size() > bytes.size() / 2) return "more points than the bytes can hold";
    try {
      uff_receptance(d, FrfOrdinate::Accelerance, "fuzz.uff");
    } catch (const InputError&) {
    } catch (const std::exception& e) {
      return std::string("uff_receptance threw ") + typeid(e).name() + ": " + e.what();
    }
  }
  try {
    select_dataset58(f, {});
  } catch (const InputError&) {
  } catch (const std::exception& e) {
    return std::string("select_dataset58 threw ") + typeid(e).name() + ": " + e.what();
  }
  // Whatever was read and fits the format is written and read back alike.
  std::vector<UffDataset58> writable;
  for (const UffDataset58& d : f.functions) {
    try {
      d.check();
      writable.push_back(d);
    } catch (const InvalidArgument&) {}
  }
  if (!writable.empty()) {
    const UffFile again = parse_uff(format_uff(writable, {.binary = writable.size() % 2 == 0}).bytes, "again.uff");
    if (again.functions.size() != writable.size()) return "a written file reads back with another dataset count";
    for (std::size_t k = 0; k < writable.size(); ++k)
      if (again.functions[k].size() != writable[k].size()) return "a written dataset reads back with another length";
  }
  return {};
}

}  // namespace

TEST(UffFuzz, MutatedAndTruncatedFilesNeverCrashTheReader) {
  const std::vector<std::string> seeds = uff_seeds();
  std::mt19937 rng(20240611);
  int cases = 0;
  for (int round = 0; round < 160; ++round) {
    for (std::size_t s = 0; s < seeds.size(); ++s, ++cases) {
      const std::string input = mutate(seeds[s], rng);
      const std::string broken = exercise(input);
      ASSERT_TRUE(broken.empty()) << "case " << cases << " (seed file " << s << "): " << broken;
    }
  }
  // Every truncation point of a small binary and a small ASCII file.
  for (const std::size_t s : {std::size_t{9}, std::size_t{13}, std::size_t{14}}) {
    for (std::size_t cut = 0; cut <= seeds[s].size(); ++cut, ++cases) {
      const std::string broken = exercise(seeds[s].substr(0, cut));
      ASSERT_TRUE(broken.empty()) << "truncated at " << cut << " (seed file " << s << "): " << broken;
    }
  }
  EXPECT_GT(cases, 5000);
}

TEST(UffFuzz, RandomBytesAndRandomLines) {
  std::mt19937 rng(7);
  const char* const lines[] = {"    -1",
                               "    58",
                               "    58b     1     2          11          16     0     0",
                               "    4         0    0         0 NONE               1   3 NONE               2   1",
                               "         6         2         1  1.00000E+01  5.00000E+00  0.00000E+00",
                               "        18    0    0    0 Frequency            Hz",
                               " 1.0E+00 2.0E+00 3.0E+00",
                               "NONE",
                               "  2414",
                               "",
                               "\x01\x02\xff\xfe"};
  for (int k = 0; k < 1500; ++k) {
    std::string s;
    if (k % 2 == 0) {
      const std::size_t n = std::uniform_int_distribution<std::size_t>(0, 3000)(rng);
      for (std::size_t i = 0; i < n; ++i) s += static_cast<char>(rng() & 0xFF);
    } else {
      for (std::size_t i = std::uniform_int_distribution<std::size_t>(0, 60)(rng); i > 0; --i)
        s += std::string(lines[rng() % std::size(lines)]) + (rng() % 7 == 0 ? "\r\n" : "\n");
    }
    const std::string broken = exercise(s);
    ASSERT_TRUE(broken.empty()) << "case " << k << ": " << broken;
  }
}

TEST(UffFuzz, CutProTextThrowsOnlyInputError) {
  std::ostringstream seed;
  seed << "Freq\tHz\tReal\tm/N\tImag\tm/N\n";
  for (int i = 0; i < 40; ++i) seed << 10 * i << '\t' << 1e-6 * i << '\t' << -2e-7 * i << '\n';
  std::mt19937 rng(11);
  int parsed = 0;
  for (int k = 0; k < 2000; ++k) {
    const std::string input = mutate(seed.str(), rng);
    try {
      const FrfText t = parse_cutpro_frf(input, "fuzz.frf");
      ASSERT_EQ(t.series.frequency_hz.size(), t.series.values.size());
      for (std::size_t i = 1; i < t.series.size(); ++i) ASSERT_GT(t.series.frequency_hz[i], t.series.frequency_hz[i - 1]);
      ++parsed;
    } catch (const InputError&) {
    } catch (const std::exception& e) {
      FAIL() << "case " << k << ": " << typeid(e).name() << ": " << e.what();
    }
  }
  EXPECT_GT(parsed, 50);  // the mutations leave many files readable (83 of 2000 with this seed): the happy path too
}

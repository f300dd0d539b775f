// Shared helpers for the file tests: a scratch folder per test, running the command line, and the
// message checks of uff_test.cpp.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <initializer_list>
#include <string>
#include <utility>
#include <vector>

#include "toolpoint/io/io.hpp"

namespace toolpoint::test {

// A fresh folder per test (named after the test and the process), removed afterwards.
class TempDir {
 public:
  explicit TempDir(const std::string& prefix = "toolpoint_test") {
    const auto* info = ::testing::UnitTest::GetInstance()->current_test_info();
    path_ = std::filesystem::temp_directory_path() /
            (prefix + "_" + std::to_string(::getpid()) + "_" + info->test_suite_name() + "_" + info->name());
    std::filesystem::remove_all(path_);
    std::filesystem::create_directories(path_);
  }
  ~TempDir() { std::filesystem::remove_all(path_); }
  TempDir(const TempDir&) = delete;
  TempDir& operator=(const TempDir&) = delete;
  std::string operator/(const std::string& leaf) const { return (path_ / leaf).string(); }

 private:
  std::filesystem::path path_;
};

// The command-line tool is there for the tests of toolpoint_cli_tests only (tests/cli_*.cpp,
// tests/tutorial_test.cpp; CMakeLists.txt): the library's tests build and run without it.
#ifdef TOOLPOINT_CLI
// `toolpoint ARGS` (TOOLPOINT_CLI); stdout and stderr together in *output. Returns the exit code.
inline int run_toolpoint(const std::string& args, std::string* output = nullptr) {
  const std::string log =
      (std::filesystem::temp_directory_path() / ("toolpoint_cli_log_" + std::to_string(::getpid()) + ".txt")).string();
  const int status = std::system((std::string(TOOLPOINT_CLI) + " " + args + " > " + log + " 2>&1").c_str());
  if (output) {
    std::ifstream in(log, std::ios::binary);
    std::stringstream ss;
    ss << in.rdbuf();
    *output = ss.str();
  }
  std::filesystem::remove(log);
  return WIFEXITED(status) ? WEXITSTATUS(status) : -1;
}
#endif

// A CSV table as toolpoint writes it ('#' comment lines, one header line, numbers; "nan" read as NaN),
// read independently of the library's readers.
inline Table read_csv_table(const std::string& path) {
  std::ifstream in(path);
  Table t;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::stringstream ss(line);
    std::string cell;
    if (t.columns.empty()) {
      while (std::getline(ss, cell, ',')) t.columns.push_back(cell);
      continue;
    }
    // Every cell, a trailing empty one included; an empty cell (no value) reads as NaN.
    std::vector<double> row;
    for (std::size_t start = 0;;) {
      const std::size_t comma = line.find(',', start);
      cell = line.substr(start, comma == std::string::npos ? std::string::npos : comma - start);
      row.push_back(cell.empty() ? std::nan("") : std::strtod(cell.c_str(), nullptr));
      if (comma == std::string::npos) break;
      start = comma + 1;
    }
    t.rows.push_back(std::move(row));
  }
  return t;
}

// PNG (ISO/IEC 15948): 8-byte signature, then the IHDR chunk (length 13) whose data begin with
// the width and height as big-endian 32-bit integers.
inline std::pair<unsigned, unsigned> png_size(const std::string& bytes) {
  const std::string signature("\x89PNG\r\n\x1a\n", 8);
  if (bytes.size() < 33 || bytes.compare(0, 8, signature) != 0 || bytes.compare(12, 4, "IHDR") != 0) return {0, 0};
  auto be32 = [&](std::size_t at) {
    unsigned v = 0;
    for (std::size_t k = 0; k < 4; ++k) v = (v << 8) | static_cast<unsigned char>(bytes[at + k]);
    return v;
  };
  if (be32(8) != 13) return {0, 0};
  return {be32(16), be32(20)};
}

}  // namespace toolpoint::test

// Message checks: `part` in `s`; every one of `parts` in one message.
namespace uff_test {

inline bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

// Whether one message holds every part.
inline bool any_contains(const std::vector<std::string>& messages, std::initializer_list<const char*> parts) {
  for (const auto& s : messages) {
    bool all = true;
    for (const char* p : parts) all = all && contains(s, p);
    if (all) return true;
  }
  return false;
}

}  // namespace uff_test

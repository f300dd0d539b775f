// A command's --help read by the CLI tests of the option tables (cli_option_fields_more_test.cpp,
// cli_option_fields_measured_test.cpp): the line registering a flag and the unit on it.
#pragma once

#include <gtest/gtest.h>

#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "support/scratch.hpp"

namespace toolpoint::test {

// The line of `help` that registers `flag` ("  --spacing FLOAT…", or after a short name
// "  -w,--window INT…"), or "" if none does.
inline std::string flag_help_line(const std::string& help, const std::string& flag) {
  std::istringstream in(help);
  for (std::string line; std::getline(in, line);) {
    std::size_t start = line.find_first_not_of(' ');
    if (start == std::string::npos) continue;
    if (line.compare(start, 2, "--") != 0 && line[start] == '-' && line.find(',', start) != std::string::npos)
      start = line.find(',', start) + 1;  // a short name first
    if (line.compare(start, flag.size() + 1, flag + " ") == 0 || line.substr(start) == flag) return line;
  }
  return {};
}

// Every flag in `command --help`, with its unit in brackets on its line ("" for a switch: none).
inline void expect_flags_in_help(const std::string& command, const std::vector<std::pair<std::string, std::string>>& flags) {
  std::string help;
  ASSERT_EQ(run_toolpoint(command + " --help", &help), 0) << help;
  for (const auto& [flag, unit] : flags) {
    const std::string line = flag_help_line(help, flag);
    EXPECT_NE(line, "") << flag << " missing from " << command << " --help";
    if (!unit.empty()) EXPECT_NE(line.find("[" + unit + "]"), std::string::npos) << line;
  }
}

}  // namespace toolpoint::test

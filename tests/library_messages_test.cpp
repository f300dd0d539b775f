// The library's messages name its own fields and functions (`FrfReadOptions::units`,
// `write_joint_file`), never the CLI's flags or commands: the CLI maps the one to the other in one
// place (with_flags, apps/toolpoint/common.cpp), and a library user has no `--units` to give.
//
// Checked on the source text: every string literal under src/ and include/ is searched for a flag
// (`--` and a lower-case letter) and for "toolpoint COMMAND", the commands being the CLI's
// (apps/toolpoint/cmd_COMMAND.cpp). Text that is file content rather than a message, and may name
// the tool, is allowed by name below.
#include <gtest/gtest.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <iterator>
#include <string>
#include <string_view>
#include <vector>

#include "toolpoint/io/io.hpp"

namespace {

namespace fs = std::filesystem;

struct Literal {
  std::size_t line = 0;  // where it opens
  std::string text;      // as written between the quotes (escapes kept)
};

bool identifier_char(char c) { return std::isalnum(static_cast<unsigned char>(c)) || c == '_'; }

// The string literals of C++ source (ordinary and raw), comments and character literals skipped.
std::vector<Literal> string_literals(std::string_view src) {
  std::vector<Literal> out;
  std::size_t line = 1;
  const auto lines_in = [&](std::size_t from, std::size_t to) {
    return static_cast<std::size_t>(std::count(src.begin() + static_cast<std::ptrdiff_t>(from),
                                               src.begin() + static_cast<std::ptrdiff_t>(std::min(to, src.size())), '\n'));
  };
  std::size_t i = 0;
  while (i < src.size()) {
    const char c = src[i];
    if (c == '\n') {
      ++line;
      ++i;
    } else if (src.substr(i, 2) == "//") {
      i = std::min(src.find('\n', i), src.size());
    } else if (src.substr(i, 2) == "/*") {
      const std::size_t end = std::min(src.find("*/", i + 2), src.size());
      line += lines_in(i, end);
      i = end + 2;
    } else if (c == '\'') {
      const bool separator = i > 0 && std::isdigit(static_cast<unsigned char>(src[i - 1])) && i + 1 < src.size() &&
                             std::isalnum(static_cast<unsigned char>(src[i + 1]));  // 1'000
      ++i;
      if (!separator) {
        while (i < src.size() && src[i] != '\'') i += src[i] == '\\' ? 2 : 1;
        ++i;
      }
    } else if (c == 'R' && src.substr(i + 1, 1) == "\"" &&
               (i == 0 || !identifier_char(src[i - 1]) || src[i - 1] == '8' || src[i - 1] == 'u' || src[i - 1] == 'U' ||
                src[i - 1] == 'L')) {
      const std::size_t open = src.find('(', i + 2);
      const std::string close = ")" + std::string(src.substr(i + 2, open - i - 2)) + "\"";
      const std::size_t end = std::min(src.find(close, open), src.size());
      out.push_back({line, std::string(src.substr(open + 1, end - open - 1))});
      line += lines_in(i, end);
      i = end + close.size();
    } else if (c == '"') {
      std::size_t j = i + 1;
      while (j < src.size() && src[j] != '"' && src[j] != '\n') j += src[j] == '\\' ? 2 : 1;
      out.push_back({line, std::string(src.substr(i + 1, j - i - 1))});
      i = j + 1;
    } else {
      ++i;
    }
  }
  return out;
}

// What in `text` names a CLI flag or command, or "" when nothing does.
std::string cli_name_in(std::string_view text, const std::vector<std::string>& commands) {
  for (std::size_t at = text.find("--"); at != std::string_view::npos; at = text.find("--", at + 1))
    if (at + 2 < text.size() && std::islower(static_cast<unsigned char>(text[at + 2]))) {
      std::size_t end = at + 2;
      while (end < text.size() && (identifier_char(text[end]) || text[end] == '-')) ++end;
      return std::string(text.substr(at, end - at));
    }
  for (const std::string& command : commands) {
    const std::string phrase = "toolpoint " + command;
    for (std::size_t at = text.find(phrase); at != std::string_view::npos; at = text.find(phrase, at + 1))
      if (at + phrase.size() == text.size() || !identifier_char(text[at + phrase.size()])) return phrase;
  }
  return {};
}

// The CLI's commands, from its source files (one per command).
std::vector<std::string> cli_commands() {
  std::vector<std::string> commands;
  for (const auto& e : fs::directory_iterator(fs::path(TOOLPOINT_SOURCE_DIR) / "apps" / "toolpoint")) {
    const std::string name = e.path().filename().string();
    if (name.rfind("cmd_", 0) == 0 && e.path().extension() == ".cpp") commands.push_back(name.substr(4, name.size() - 8));
  }
  return commands;
}

// Literals that may name the tool: file content for the files' readers, and identifiers that are
// part of a file format.
struct Allowed {
  const char* file;      // relative to the source folder
  const char* fragment;  // a piece of the literal
  const char* why;
};
const Allowed kAllowed[] = {
    {"src/joint_file.cpp", "Use it with e.g. `toolpoint predict", "the comment written at the top of every joint file"},
    {"src/studies/plan.cpp", "toolpoint plan 2", "the plan fingerprint's salt: changing it changes every fingerprint"},
    {"src/studies/plan_io.cpp", "toolpoint plan part", "the part files' format tag"},
    {"src/studies/plan_io.cpp", "# toolpoint plan: ", "the first comment line of the plan's CSV files"},
};

TEST(LibraryMessages, TheScannerFindsFlagsAndCommandsInLiteralsOnly) {
  const std::vector<std::string> commands{"convert", "plan"};
  const std::string src =
      "// a comment: --units, `toolpoint convert`\n"
      "/* --units\n toolpoint plan */ const char c = '\"'; int n = 1'000;\n"
      "throw X(\"rescale (--units)\", \"see `toolpoint convert FILE --list`\");\n"
      "f(\"toolpoint planning, toolpoint-x, a -- b, --1\");\n"
      "g(R\"x(raw \"--format\")x\", u8R\"(toolpoint plan)\");\n";
  const std::vector<Literal> lits = string_literals(src);
  ASSERT_EQ(lits.size(), 5u);
  EXPECT_EQ(lits[0].line, 4u);
  EXPECT_EQ(cli_name_in(lits[0].text, commands), "--units");
  EXPECT_EQ(cli_name_in(lits[1].text, commands), "--list");
  EXPECT_EQ(cli_name_in(lits[2].text, commands), "");
  EXPECT_EQ(lits[3].line, 6u);
  EXPECT_EQ(lits[3].text, "raw \"--format\"");
  EXPECT_EQ(cli_name_in(lits[3].text, commands), "--format");
  EXPECT_EQ(cli_name_in(lits[4].text, commands), "toolpoint plan");
}

TEST(LibraryMessages, NameNoCliFlagOrCommand) {
  const std::vector<std::string> commands = cli_commands();
  ASSERT_GE(commands.size(), 10u);
  ASSERT_NE(std::find(commands.begin(), commands.end(), "convert"), commands.end());
  const fs::path root(TOOLPOINT_SOURCE_DIR);
  std::vector<bool> used(std::size(kAllowed), false);
  std::string found;
  std::size_t files = 0;
  for (const char* folder : {"src", "include"})
    for (const auto& e : fs::recursive_directory_iterator(root / folder)) {
      const std::string ext = e.path().extension().string();
      if (!e.is_regular_file() || (ext != ".cpp" && ext != ".hpp")) continue;
      ++files;
      const std::string rel = fs::relative(e.path(), root).generic_string();
      for (const Literal& lit : string_literals(toolpoint::read_text_file(e.path().string()))) {
        const std::string name = cli_name_in(lit.text, commands);
        if (name.empty()) continue;
        bool allowed = false;
        for (std::size_t a = 0; a < std::size(kAllowed); ++a)
          if (rel == kAllowed[a].file && lit.text.find(kAllowed[a].fragment) != std::string::npos) {
            allowed = true;
            used[a] = true;
          }
        if (!allowed) found += "\n  " + rel + ":" + std::to_string(lit.line) + ": " + name + " in \"" + lit.text + "\"";
      }
    }
  EXPECT_GT(files, 50u);
  EXPECT_TRUE(found.empty()) << "library text names a CLI flag or command (name the library's field or function, and "
                                "map it to the flag in with_flags, apps/toolpoint/common.cpp):"
                             << found;
  for (std::size_t a = 0; a < std::size(kAllowed); ++a)
    EXPECT_TRUE(used[a]) << "allowed but not found (drop it from kAllowed): " << kAllowed[a].file << ": " << kAllowed[a].fragment;
}

}  // namespace

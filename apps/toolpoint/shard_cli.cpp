// toolpoint CLI: what the sharded commands share (plan, simulate map): the --shard/--part options,
// the commands a merge prints to mend a set of parts, and the options that run a study again.
#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fmt/format.h>
#include <string_view>

#include "cli.hpp"
#include "toolpoint/error.hpp"

namespace toolpoint::cli {

ShardId shard_options(const std::string& shard, const std::string& part, bool whole_outputs, const std::string& what,
                      const std::string& merge) {
  if (shard.empty()) {
    if (!part.empty())
      throw InvalidArgument("--part needs --shard I/N",
                            fmt::format("add --shard 0/1 to write the whole {} as one part, or drop --part", what));
    return {};
  }
  const auto [index, count] = parse_shard(shard, "--shard");
  if (part.empty())
    throw InvalidArgument(fmt::format("--shard needs --part FILE: where this shard's part of the {} goes", what),
                          "add --part part-I.json");
  if (whole_outputs)
    throw InvalidArgument(fmt::format("--shard writes only its --part file: --output, --plot and --json belong to `{}`", merge),
                          fmt::format("drop them here and give them to `{} PARTS...`", merge));
  return {index, count};
}

std::string mending_commands(const ShardSetCheck& c, const ShardCommand& rerun) {
  std::vector<std::string> steps;
  if (!c.drop.empty()) {
    std::string drop = "leave out";
    for (const std::string& d : c.drop) drop += " " + d;
    steps.push_back(drop);
  }
  std::string dir;
  bool slurm_names = !c.rerun.empty();
  std::vector<int> indices;
  for (const ShardRerun& r : c.rerun) {
    indices.push_back(r.index);
    const std::filesystem::path p(r.part);
    if (p.filename() != fmt::format("part-{}.json", r.index) || (!dir.empty() && p.parent_path().string() != dir))
      slurm_names = false;
    dir = p.parent_path().string();
  }
  if (slurm_names && c.rerun.size() > 4) {
    std::string list;
    for (int i : indices) list += fmt::format("{}{}", list.empty() ? "" : " ", i);
    steps.push_back(fmt::format("run the missing shards again: for i in {}; do {} --shard $i/{} --part {}/part-$i.json; done",
                                list, rerun.command, c.count, dir.empty() ? "." : dir));
  } else {
    for (const ShardRerun& r : c.rerun)
      steps.push_back(fmt::format("run shard {} again: {} --shard {}/{} --part {}", r.index, rerun.command, r.index, c.count,
                                  r.part.empty() ? fmt::format("part-{}.json", r.index) : r.part));
  }
  if (slurm_names) {
    std::string list = shard_list(indices);
    list.erase(std::remove(list.begin(), list.end(), ' '), list.end());
    steps.push_back("or, in the Slurm array: " + rerun.array(list, dir.empty() ? "." : dir, c.count));
  }
  std::string fix;
  for (const std::string& s : steps) fix += (fix.empty() ? "" : "; ") + s;
  return fix + "; then merge again";
}

namespace {

// A word for a POSIX shell: as it is when it holds only characters no shell treats specially,
// else in single quotes (a quote inside as '\'').
std::string shell_word(const std::string& w) {
  const bool plain = !w.empty() && std::all_of(w.begin(), w.end(), [](unsigned char ch) {
    return std::isalnum(ch) || std::string_view("-_./:,=+@%^").find(static_cast<char>(ch)) != std::string_view::npos;
  });
  if (plain) return w;
  std::string q = "'";
  for (char ch : w) q += ch == '\'' ? std::string("'\\''") : std::string(1, ch);
  return q + "'";
}

}  // namespace

std::string given_options(const std::vector<const CLI::App*>& commands, std::initializer_list<const char*> leave_out) {
  std::vector<std::string> words;
  for (const CLI::App* command : commands)
    for (const CLI::Option* opt : command->get_options()) {
      const std::string name = opt->get_name();
      if (opt->count() == 0 || opt->get_positional() || name.rfind("--", 0) != 0 ||
          std::any_of(leave_out.begin(), leave_out.end(), [&](const char* l) { return name == l; }))
        continue;
      if (opt->get_expected_max() == 0) {  // a flag: given, or given as false
        if (opt->as<bool>()) words.push_back(name);
        continue;
      }
      const std::vector<std::string>& values = opt->results();
      if (opt->get_delimiter() != '\0') {
        // One word: CLI11 split the values at the delimiter (--pitch 85,95,85,95).
        std::string joined;
        for (const std::string& v : values) joined += (joined.empty() ? "" : std::string(1, opt->get_delimiter())) + v;
        words.push_back(shell_word(name + "=" + joined));
      } else {
        for (const std::string& v : values) words.push_back(shell_word(name + "=" + v));
      }
    }
  std::string out;
  for (const std::string& w : words) out += (out.empty() ? "" : " ") + w;
  return out;
}

}  // namespace toolpoint::cli

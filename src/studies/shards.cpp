// toolpoint study: shards of a study and the verdict on a set of parts (studies/shards.hpp).
#include "toolpoint/studies/shards.hpp"

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fmt/format.h>
#include <map>

namespace toolpoint {

void check_shard(const ShardId& s) {
  if (s.count < 1 || s.count > kMaxShards)
    throw InvalidArgument(fmt::format("shard count {} must lie in 1…{}", s.count, kMaxShards),
                          fmt::format("split the study into 1 to {} shards", kMaxShards));
  if (s.index == s.count)
    throw InvalidArgument(
        fmt::format("shard {} of {} does not exist: shards are counted from 0, the last is {}; an index equal to the count "
                    "comes from an array numbered from 1",
                    s.index, s.count, s.count - 1),
        fmt::format("number the tasks 0…{} (a Slurm array 0-{}, whose task id is the shard index)", s.count - 1, s.count - 1));
  if (s.index < 0 || s.index > s.count)
    throw InvalidArgument(fmt::format("shard {} of {} does not exist: shards are numbered 0…{}", s.index, s.count, s.count - 1),
                          fmt::format("give an index from 0 to {} (as many tasks as shards, counted from 0)", s.count - 1));
}

bool in_shard(std::size_t job, const ShardId& s) {
  return job % static_cast<std::size_t>(s.count) == static_cast<std::size_t>(s.index);
}

std::vector<std::size_t> shard_jobs(std::size_t jobs, const ShardId& s) {
  std::vector<std::size_t> mine;
  for (std::size_t j = static_cast<std::size_t>(s.index); j < jobs; j += static_cast<std::size_t>(s.count)) mine.push_back(j);
  return mine;
}

std::string shard_list(const std::vector<int>& indices) {
  std::vector<int> v = indices;
  std::sort(v.begin(), v.end());
  v.erase(std::unique(v.begin(), v.end()), v.end());
  std::string out;
  for (std::size_t i = 0; i < v.size();) {
    std::size_t k = i;
    while (k + 1 < v.size() && v[k + 1] == v[k] + 1) ++k;
    if (!out.empty()) out += ", ";
    if (k - i >= 3) {  // a run of four or more
      out += fmt::format("{}-{}", v[i], v[k]);
      i = k + 1;
    } else {
      out += std::to_string(v[i++]);
    }
  }
  return out;
}

std::string sibling_part_path(const std::string& sibling, int sibling_index, int index) {
  const std::filesystem::path p(sibling);
  const std::string name = p.filename().string();
  // The last run of digits in the name whose value is the sibling's index (zero padding kept).
  for (std::size_t end = name.size(); end > 0;) {
    if (!std::isdigit(static_cast<unsigned char>(name[end - 1]))) {
      --end;
      continue;
    }
    std::size_t begin = end;
    while (begin > 0 && std::isdigit(static_cast<unsigned char>(name[begin - 1]))) --begin;
    const std::string run = name.substr(begin, end - begin);
    if (run.size() <= 9 && std::stoi(run) == sibling_index) {
      std::string digits = std::to_string(index);
      if (run.size() > 1 && run[0] == '0' && digits.size() < run.size()) digits.insert(0, run.size() - digits.size(), '0');
      std::string renamed = name;
      renamed.replace(begin, end - begin, digits);
      return (p.parent_path() / renamed).string();
    }
    end = begin;
  }
  return {};
}

ShardSetCheck check_shard_set(const std::vector<PartLabel>& parts, const std::vector<ShardSetCheck>& unreadable) {
  ShardSetCheck c;
  if (parts.empty() && unreadable.empty()) {
    c.problems.push_back("no parts given");
    return c;
  }
  // The run: the largest group with one fingerprint and one count (the first part's on a tie).
  std::map<std::pair<std::uint64_t, int>, std::size_t> size;
  for (const PartLabel& p : parts) ++size[{p.fingerprint, p.shard.count}];
  for (const ShardSetCheck& u : unreadable) ++size[{u.fingerprint, u.count}];
  std::pair<std::uint64_t, int> run = parts.empty() ? std::pair{unreadable.front().fingerprint, unreadable.front().count}
                                                    : std::pair{parts.front().fingerprint, parts.front().shard.count};
  for (const auto& [key, n] : size)
    if (n > size[run]) run = key;
  c.fingerprint = run.first;
  c.count = run.second;
  for (const PartLabel& p : parts)
    if (p.fingerprint == run.first && p.shard.count == run.second && !p.study.empty()) {
      c.study = p.study;
      break;
    }
  for (const ShardSetCheck& u : unreadable)
    if (c.study.empty() && u.fingerprint == run.first && u.count == run.second) c.study = u.study;
  const std::string study = c.study.empty() ? "" : fmt::format(", study {}", c.study);
  std::vector<int> holder(static_cast<std::size_t>(c.count), -1);
  std::map<int, std::vector<std::string>> copies;
  for (std::size_t i = 0; i < parts.size(); ++i) {
    const PartLabel& p = parts[i];
    if (p.fingerprint != run.first) {
      c.drop.push_back(p.source);
      c.problems.push_back(fmt::format("{} (shard {} of {}) belongs to another study: fingerprint {:016x}{}, not {:016x}{}",
                                       p.source, p.shard.index, p.shard.count, p.fingerprint,
                                       p.study.empty() ? "" : ", study " + p.study, run.first, study));
      continue;
    }
    if (p.shard.count != run.second) {
      c.drop.push_back(p.source);
      c.problems.push_back(fmt::format("{} is shard {} of {}, but the other parts split the study into {}", p.source,
                                       p.shard.index, p.shard.count, run.second));
      continue;
    }
    if (p.shard.index < 0 || p.shard.index >= c.count) {  // a part file refuses this when read; a caller's label may not
      c.drop.push_back(p.source);
      c.problems.push_back(fmt::format("{}: shard index {} outside 0…{}", p.source, p.shard.index, c.count - 1));
      continue;
    }
    int& h = holder[static_cast<std::size_t>(p.shard.index)];
    if (h >= 0) {
      c.drop.push_back(p.source);
      auto& names = copies[p.shard.index];
      if (names.empty()) names.push_back(parts[static_cast<std::size_t>(h)].source);
      names.push_back(p.source);
    } else {
      h = static_cast<int>(i);
    }
  }
  for (const auto& copy : copies) {
    const int index = copy.first;
    const std::vector<std::string>& names = copy.second;  // not a structured binding: clang 14 cannot capture one
    std::string list;
    for (std::size_t k = 0; k < names.size(); ++k) list += (k ? (k + 1 == names.size() ? " and " : ", ") : "") + names[k];
    const bool same_file = std::all_of(names.begin(), names.end(), [&](const std::string& n) { return n == names[0]; });
    c.problems.push_back(same_file ? fmt::format("shard {} of {}: {} is given {} times", index, c.count, names[0], names.size())
                                   : fmt::format("shard {} of {} is given {} times: {}", index, c.count, names.size(), list));
  }
  // Unreadable parts: their shards are run again into their own files, unless a good part holds them.
  std::map<int, std::string> damaged;
  for (const ShardSetCheck& u : unreadable) {
    c.problems.insert(c.problems.end(), u.problems.begin(), u.problems.end());
    for (const ShardRerun& r : u.rerun) {
      const bool ours = (u.fingerprint == run.first || u.fingerprint == 0) && u.count == run.second && r.index >= 0 &&
                        r.index < c.count;
      if (ours && holder[static_cast<std::size_t>(r.index)] < 0 && !damaged.count(r.index)) damaged[r.index] = r.part;
      else c.drop.push_back(r.part);
    }
  }
  std::vector<int> missing;
  for (int i = 0; i < c.count; ++i)
    if (holder[static_cast<std::size_t>(i)] < 0 && !damaged.count(i)) missing.push_back(i);
  // Where a missing shard's part goes: named like a part of the run whose name holds its index.
  std::string sibling;
  int sibling_index = 0;
  for (int i = 0; i < c.count && sibling.empty(); ++i) {
    const int h = holder[static_cast<std::size_t>(i)];
    if (h >= 0 && !sibling_part_path(parts[static_cast<std::size_t>(h)].source, i, i).empty()) {
      sibling = parts[static_cast<std::size_t>(h)].source;
      sibling_index = i;
    }
  }
  for (int i = 0; i < c.count; ++i) {
    if (const auto d = damaged.find(i); d != damaged.end()) c.rerun.push_back({i, d->second});
    else if (holder[static_cast<std::size_t>(i)] < 0)
      c.rerun.push_back({i, sibling.empty() ? "" : sibling_part_path(sibling, sibling_index, i)});
  }
  if (!missing.empty()) {
    std::string why;
    if (missing.size() == 1 && missing.front() == 0 && c.count > 1)
      why = " (only shard 0: were the tasks numbered from 1, as a Slurm array 1-N? Shards are counted from 0)";
    c.problems.push_back(fmt::format("shard(s) {} of {} missing{}", shard_list(missing), c.count, why));
  }
  return c;
}

void check_jobs_placed(const std::vector<PartLabel>& parts, const std::vector<std::vector<std::size_t>>& jobs_of,
                       std::size_t jobs) {
  std::vector<bool> have(jobs, false);
  for (std::size_t p = 0; p < parts.size() && p < jobs_of.size(); ++p)
    for (std::size_t j : jobs_of[p]) {
      if (j >= jobs)
        throw InputError(fmt::format("{}: job {} is not in the run ({} jobs)", parts[p].source, j, jobs),
                         "the part file is damaged: run its shard again");
      if (!in_shard(j, parts[p].shard) || have[j])
        throw InputError(fmt::format("{}: job {} does not belong to shard {} of {}", parts[p].source, j, parts[p].shard.index,
                                     parts[p].shard.count),
                         "the part file is damaged: run its shard again");
      have[j] = true;
    }
  for (std::size_t j = 0; j < jobs; ++j)
    if (!have[j])
      throw InputError(fmt::format("job {} is in none of the parts", j), "the part files are damaged: run their shards again");
}

namespace {

std::string verdict_text(const ShardSetCheck& c) {
  std::string what = c.count > 0 ? fmt::format("the parts are not one whole run of {} shards (fingerprint {:016x}{}): ", c.count,
                                               c.fingerprint, c.study.empty() ? "" : ", study " + c.study)
                                 : std::string();
  for (std::size_t i = 0; i < c.problems.size(); ++i) what += (i ? "; " : "") + c.problems[i];
  return what;
}

std::string verdict_hint(const ShardSetCheck& c, const std::string& run_function) {
  std::string hint;
  if (!c.drop.empty()) {
    hint = "leave out ";
    for (std::size_t i = 0; i < c.drop.size(); ++i) hint += (i ? ", " : "") + c.drop[i];
  }
  if (!c.rerun.empty()) {
    std::vector<int> idx;
    for (const ShardRerun& r : c.rerun) idx.push_back(r.index);
    if (!hint.empty()) hint += "; ";
    hint += fmt::format("run shard(s) {} of {} again ({} with those indices and count {})", shard_list(idx), c.count,
                        run_function, c.count);
  }
  if (hint.empty()) hint = "give every part of the run once";
  return hint + ", then merge again";
}

}  // namespace

ShardSetError::ShardSetError(ShardSetCheck check, const std::string& run_function)
    : InputError(verdict_text(check), verdict_hint(check, run_function)), check_(std::move(check)) {}

void throw_unless_whole(const ShardSetCheck& check, const std::string& run_function) {
  if (!check.ok() || !check.problems.empty()) throw ShardSetError(check, run_function);
}

}  // namespace toolpoint

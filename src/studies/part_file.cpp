// toolpoint (internal): shards and part files of sharded studies (part_file.hpp).
#include "part_file.hpp"

#include <charconv>
#include <cmath>
#include <fmt/format.h>
#include <limits>

#include "toolpoint/error.hpp"

namespace toolpoint::parts {

void check_shard(int index, int count) {
  if (count < 1 || count > 100000)
    throw InvalidArgument(fmt::format("shard count {} must lie in 1…100000", count), "split the work into 1 to 100000 parts");
  if (index < 0 || index >= count)
    throw InvalidArgument(fmt::format("shard {} of {} does not exist: shards are numbered 0…{}", index, count, count - 1),
                          "give an index from 0 to the count less one (a Slurm array 0-(N-1) gives $SLURM_ARRAY_TASK_ID so)");
}

std::vector<std::size_t> shard_jobs(std::size_t jobs, int index, int count) {
  check_shard(index, count);
  std::vector<std::size_t> mine;
  for (std::size_t j = static_cast<std::size_t>(index); j < jobs; j += static_cast<std::size_t>(count)) mine.push_back(j);
  return mine;
}

void check_origins(const std::vector<Origin>& parts, const std::vector<std::string>& sources, std::size_t jobs,
                   const std::string& what, const std::string& rerun) {
  const auto name = [&](std::size_t p) { return p < sources.size() ? sources[p] : fmt::format("part {}", p + 1); };
  if (parts.empty()) throw InvalidArgument("no parts to merge", "give every part file of the run");
  const Origin& first = parts.front();
  const int count = first.count;
  for (std::size_t p = 0; p < parts.size(); ++p)
    if (parts[p].fingerprint != first.fingerprint)
      throw InputError(fmt::format("{} and {} belong to different {} (fingerprints {:016x} and {:016x})", name(0), name(p), what,
                                   first.fingerprint, parts[p].fingerprint),
                       "merge only the parts of one run: the same inputs and options, every shard once");
  std::vector<int> seen(static_cast<std::size_t>(std::max(count, 1)), -1);
  for (std::size_t p = 0; p < parts.size(); ++p) {
    const Origin& q = parts[p];
    if (q.count != count)
      throw InputError(fmt::format("{} is shard {} of {}, but {} is of {}", name(p), q.index, q.count, name(0), count),
                       "merge the parts of one split: the same shard count N for every part");
    if (q.index < 0 || q.index >= count)
      throw InputError(fmt::format("{}: shard index {} outside 0…{}", name(p), q.index, count - 1));
    int& s = seen[static_cast<std::size_t>(q.index)];
    if (s >= 0)
      throw InputError(fmt::format("{} and {} are both shard {} of {}", name(static_cast<std::size_t>(s)), name(p), q.index,
                                   count),
                       "give each part file once");
    s = static_cast<int>(p);
  }
  std::string missing;
  std::size_t n_missing = 0;
  for (int i = 0; i < count; ++i)
    if (seen[static_cast<std::size_t>(i)] < 0) missing += (n_missing++ ? ", " : "") + std::to_string(i);
  if (n_missing > 0)
    throw InputError(fmt::format("shard(s) {} of {} missing: {} part(s) given", missing, count, parts.size()),
                     fmt::format("run the missing shards ({} with their index) and merge every part", rerun));
  std::vector<bool> have(jobs, false);
  for (std::size_t p = 0; p < parts.size(); ++p)
    for (std::size_t j : parts[p].jobs) {
      if (j >= jobs) throw InputError(fmt::format("{}: job {} is not in the run ({} jobs)", name(p), j, jobs));
      if (j % static_cast<std::size_t>(count) != static_cast<std::size_t>(parts[p].index) || have[j])
        throw InputError(fmt::format("{}: job {} does not belong to shard {} of {}", name(p), j, parts[p].index, count),
                         "the part file is damaged: run its shard again");
      have[j] = true;
    }
  for (std::size_t j = 0; j < jobs; ++j)
    if (!have[j])
      throw InputError(fmt::format("job {} is in none of the parts", j), "the part files are damaged: run their shards again");
}

std::string hex(double x) { return fmt::format("{:a}", x); }

nlohmann::json hexes(const std::vector<double>& v) {
  nlohmann::json a = nlohmann::json::array();
  for (double x : v) a.push_back(hex(x));
  return a;
}

void Reader::fail(const std::string& message) const {
  throw InputError(fmt::format("{}: {}", source, message),
                   fmt::format("the part file is damaged or not {}: run its shard again", what));
}

const nlohmann::json& Reader::at(const nlohmann::json& j, const char* key, const std::string& path) const {
  if (!j.is_object() || !j.contains(key)) fail(fmt::format("missing '{}{}'", path, key));
  return j.at(key);
}

double Reader::number(const nlohmann::json& j, const std::string& name) const {
  if (!j.is_string()) fail(fmt::format("{} is not a hexadecimal number", name));
  const std::string s = j.get<std::string>();
  if (s == "inf") return std::numeric_limits<double>::infinity();
  if (s == "-inf") return -std::numeric_limits<double>::infinity();
  if (s == "nan" || s == "-nan") return std::numeric_limits<double>::quiet_NaN();
  const bool negative = !s.empty() && s[0] == '-';
  const std::size_t at0 = negative ? 1 : 0;
  if (s.compare(at0, 2, "0x") != 0) fail(fmt::format("{} = '{}' is not a hexadecimal number", name, s));
  double v = 0.0;
  const char* first = s.data() + at0 + 2;
  const auto [end, ec] = std::from_chars(first, s.data() + s.size(), v, std::chars_format::hex);
  if (ec != std::errc() || end != s.data() + s.size()) fail(fmt::format("{} = '{}' is not a hexadecimal number", name, s));
  return negative ? -v : v;
}

double Reader::number(const nlohmann::json& j, const char* key, const std::string& path) const {
  return number(at(j, key, path), path + key);
}

std::vector<double> Reader::numbers(const nlohmann::json& j, const char* key, const std::string& path) const {
  const nlohmann::json& a = at(j, key, path);
  if (!a.is_array()) fail(fmt::format("'{}{}' is not an array", path, key));
  std::vector<double> v;
  for (std::size_t i = 0; i < a.size(); ++i) v.push_back(number(a[i], fmt::format("{}{}[{}]", path, key, i)));
  return v;
}

std::uint64_t Reader::hash(const nlohmann::json& j, const char* key, const std::string& path) const {
  const std::string s = get<std::string>(j, key, path);
  std::uint64_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v, 16);
  if (ec != std::errc() || end != s.data() + s.size()) fail(fmt::format("'{}{}' is not a hexadecimal hash", path, key));
  return v;
}

namespace {

// FNV-1a of text: the part's checksum over its jobs (the header has its fingerprint).
std::uint64_t text_hash(const std::string& text) {
  Fnv1a f;
  f.bytes(text.data(), text.size());
  return f.h;
}

}  // namespace

std::string format_part(const std::string& format, int version, std::uint64_t fingerprint, int index, int count,
                        nlohmann::json header, nlohmann::json jobs) {
  nlohmann::json j;
  j["format"] = format;
  j["version"] = version;
  j["fingerprint"] = fmt::format("{:016x}", fingerprint);
  j["shard"] = {{"index", index}, {"count", count}};
  j["header"] = std::move(header);
  j["checksum"] = fmt::format("{:016x}", text_hash(jobs.dump()));
  j["jobs"] = std::move(jobs);
  return j.dump() + "\n";
}

Part parse_part(const std::string& text, const std::string& source, const std::string& format, int version,
                const std::string& what, const std::string& writer) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw InputError(fmt::format("{}: not {} file (JSON: {})", source, what, e.what()),
                     fmt::format("give what {} wrote", writer));
  }
  if (!j.is_object() || !j.contains("format") || j["format"] != format)
    throw InputError(fmt::format("{}: not {} file (no \"format\": \"{}\")", source, what, format),
                     fmt::format("give what {} wrote", writer));
  const Reader r{source, what};
  if (r.get<int>(j, "version", "") != version)
    throw InputError(fmt::format("{}: {} format version {} (this toolpoint reads {})", source, what, j["version"].dump(),
                                 version),
                     "merge with the toolpoint version that wrote the parts, or run the shards again");
  Part p;
  p.header = r.at(j, "header", "");
  p.fingerprint = r.hash(j, "fingerprint", "");
  const nlohmann::json& shard = r.at(j, "shard", "");
  p.index = r.get<int>(shard, "index", "shard.");
  p.count = r.get<int>(shard, "count", "shard.");
  p.jobs = r.at(j, "jobs", "");
  if (!p.jobs.is_array()) r.fail("'jobs' is not an array");
  if (r.get<std::string>(j, "checksum", "") != fmt::format("{:016x}", text_hash(p.jobs.dump())))
    r.fail("the jobs' numbers do not match the part's checksum: edited or damaged");
  return p;
}

}  // namespace toolpoint::parts

// toolpoint (internal): the part file envelope of a sharded study (part_file.hpp).
#include "part_file.hpp"

#include <charconv>
#include <fmt/format.h>
#include <limits>
#include <optional>
#include <regex>

#include "toolpoint/error.hpp"

namespace toolpoint::part_file {

std::string hex(double x) { return fmt::format("{:a}", x); }

nlohmann::json hexes(const std::vector<double>& v) {
  nlohmann::json a = nlohmann::json::array();
  for (double x : v) a.push_back(hex(x));
  return a;
}

std::uint64_t text_hash(const std::string& text) {
  Fnv1a f;
  f.bytes(text.data(), text.size());
  return f.h;
}

std::string format_envelope(const PartKind& kind, const ShardId& shard, const std::string& study, std::uint64_t fingerprint,
                            const nlohmann::json& header, const nlohmann::json& jobs) {
  const std::string j = jobs.dump();
  return fmt::format(
      "{{\"format\":{},\"version\":{},\"shard\":{{\"index\":{},\"count\":{}}},\"study\":{},\"fingerprint\":\"{:016x}\","
      "\"header\":{},\"checksum\":\"{:016x}\",\"jobs\":{}}}\n",
      nlohmann::json(kind.format).dump(), kind.version, shard.index, shard.count, nlohmann::json(study).dump(), fingerprint,
      header.dump(), text_hash(j), j);
}

namespace {

// The shard a part was (from the start of its text, which the writer puts first), or nullopt.
std::optional<Envelope> envelope_start(const std::string& text, const PartKind& kind) {
  const std::string prefix = "{\"format\":" + nlohmann::json(kind.format).dump() +
                             ",\"version\":" + std::to_string(kind.version) + ",\"shard\":{\"index\":";
  if (text.compare(0, prefix.size(), prefix) != 0) return std::nullopt;
  static const std::regex rest(
      R"re(^(\d{1,6}),"count":(\d{1,6})\}(,"study":("(?:[^"\\]|\\.)*")(,"fingerprint":"([0-9a-f]{16})")?)?)re");
  std::smatch m;
  const std::string tail = text.substr(prefix.size(), 4096);
  if (!std::regex_search(tail, m, rest)) return std::nullopt;
  Envelope e;
  e.shard = {std::stoi(m[1].str()), std::stoi(m[2].str())};
  if (m[4].matched) {
    try {
      e.study = nlohmann::json::parse(m[4].str()).get<std::string>();
    } catch (const nlohmann::json::exception&) {}
  }
  if (m[6].matched) e.fingerprint = std::stoull(m[6].str(), nullptr, 16);  // 0: cut before it
  return e;
}

}  // namespace

void PartReader::fail(const std::string& what) const {
  if (!envelope)
    throw InputError(fmt::format("{}: {}", source, what),
                     fmt::format("the file is damaged or not a {} file: run its shard again", kind.format));
  ShardSetCheck c;
  c.count = envelope->shard.count;
  c.fingerprint = envelope->fingerprint;
  c.study = envelope->study;
  c.rerun.push_back({envelope->shard.index, source});
  c.problems.push_back(fmt::format("{} (shard {} of {}): {}", source, envelope->shard.index, envelope->shard.count, what));
  throw ShardSetError(std::move(c), kind.run_function);
}

const nlohmann::json& PartReader::at(const nlohmann::json& j, const char* key, const std::string& path) const {
  if (!j.is_object() || !j.contains(key)) fail(fmt::format("missing '{}{}'", path, key));
  return j.at(key);
}

double PartReader::number(const nlohmann::json& j, const std::string& what) const {
  if (!j.is_string()) fail(fmt::format("{} is not a hexadecimal number", what));
  std::string s = j.get<std::string>();
  if (s == "inf") return std::numeric_limits<double>::infinity();
  if (s == "-inf") return -std::numeric_limits<double>::infinity();
  if (s == "nan" || s == "-nan") return std::numeric_limits<double>::quiet_NaN();
  const bool negative = !s.empty() && s[0] == '-';
  const std::size_t at = negative ? 1 : 0;
  if (s.compare(at, 2, "0x") != 0) fail(fmt::format("{} = '{}' is not a hexadecimal number", what, s));
  double v = 0.0;
  const char* first = s.data() + at + 2;
  const auto [end, ec] = std::from_chars(first, s.data() + s.size(), v, std::chars_format::hex);
  if (ec != std::errc() || end != s.data() + s.size()) fail(fmt::format("{} = '{}' is not a hexadecimal number", what, s));
  return negative ? -v : v;
}

double PartReader::number(const nlohmann::json& j, const char* key, const std::string& path) const {
  return number(at(j, key, path), path + key);
}

std::vector<double> PartReader::numbers(const nlohmann::json& j, const char* key, const std::string& path) const {
  const nlohmann::json& a = at(j, key, path);
  if (!a.is_array()) fail(fmt::format("'{}{}' is not an array", path, key));
  std::vector<double> v;
  for (std::size_t i = 0; i < a.size(); ++i) v.push_back(number(a[i], fmt::format("{}{}[{}]", path, key, i)));
  return v;
}

std::uint64_t PartReader::hash(const nlohmann::json& j, const char* key, const std::string& path) const {
  const std::string s = get<std::string>(j, key, path);
  std::uint64_t v = 0;
  const auto [end, ec] = std::from_chars(s.data(), s.data() + s.size(), v, 16);
  if (ec != std::errc() || end != s.data() + s.size() || s.size() != 16)
    fail(fmt::format("'{}{}' = '{}' is not a 16-digit hexadecimal hash", path, key, s));
  return v;
}

Envelope parse_envelope(const std::string& text, const std::string& source, const PartKind& kind) {
  nlohmann::json j;
  try {
    j = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    if (const std::optional<Envelope> start = envelope_start(text, kind)) {
      // The writer renames a complete file into place, so this one was cut short elsewhere (a copy
      // that did not finish, a full disk on another file system) or edited.
      const PartReader r{source, kind, &*start};
      r.fail(
          fmt::format("cut short or damaged: its {} bytes are not whole JSON (it breaks at byte {}), so it is not the "
                      "file the shard wrote",
                      text.size(), e.byte));
    }
    throw InputError(fmt::format("{}: not a {} file (JSON: {})", source, kind.format, e.what()),
                     fmt::format("give what {} wrote", kind.format_function));
  }
  const PartReader plain{source, kind};
  if (!j.is_object() || !j.contains("format") || j["format"] != kind.format)
    throw InputError(fmt::format("{}: not a {} file (no \"format\": \"{}\")", source, kind.format, kind.format),
                     fmt::format("give what {} wrote", kind.format_function));
  if (plain.get<int>(j, "version", "") != kind.version)
    throw InputError(fmt::format("{}: {} format version {} (this toolpoint reads {})", source, kind.format, j["version"].dump(),
                                 kind.version),
                     "merge with the toolpoint version that wrote the parts, or run the shards again");
  Envelope e;
  const nlohmann::json& shard = plain.at(j, "shard", "");
  e.shard = {plain.get<int>(shard, "index", "shard."), plain.get<int>(shard, "count", "shard.")};
  if (e.shard.count < 1 || e.shard.count > kMaxShards || e.shard.index < 0 || e.shard.index >= e.shard.count)
    plain.fail(fmt::format("shard {} of {} does not exist (shards are counted from 0, at most {})", e.shard.index, e.shard.count,
                           kMaxShards));
  e.study = plain.get<std::string>(j, "study", "");
  e.fingerprint = plain.hash(j, "fingerprint", "");
  const PartReader r{source, kind, &e};
  for (const char* key : {"header", "jobs"}) r.at(j, key, "");
  e.header = std::move(j["header"]);
  e.jobs = std::move(j["jobs"]);
  if (!e.jobs.is_array()) r.fail("'jobs' is not an array");
  if (r.hash(j, "checksum", "") != text_hash(e.jobs.dump()))
    r.fail("the jobs' numbers do not match the part's checksum: edited or damaged");
  return e;
}

}  // namespace toolpoint::part_file

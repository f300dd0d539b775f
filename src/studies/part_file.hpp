// toolpoint (internal): the part file of a sharded study (studies/shards.hpp) — the envelope every
// sharded study's parts share; the study brings its header and jobs as JSON (plan_io.cpp does).
//
// One line of JSON whose first keys come in a fixed order, so that a file cut short still says
// which shard it held and of which study:
//   {"format":F,"version":V,"shard":{"index":I,"count":N},"study":S,"fingerprint":"%016x",
//    "header":H,"checksum":"%016x","jobs":J}
// Every double is C99 hexadecimal text (hex(), PartReader::number): reading gives the same bits,
// with inf and nan. The checksum is FNV-1a over J as nlohmann dumps it (keys sorted), so an edited
// or damaged job is refused; the fingerprint covers the header (the study checks it: it knows how
// to compute it). Files are written whole or not at all by the caller (write_text_file).
#pragma once

#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "toolpoint/studies/shards.hpp"

namespace toolpoint::part_file {

std::string hex(double x);
nlohmann::json hexes(const std::vector<double>& v);

// FNV-1a (64-bit) of text.
std::uint64_t text_hash(const std::string& text);

// What the kind of part is: its "format" text, version, the library calls that compute a shard
// and write its part (for the hints: "run_plan_part", "format_plan_part").
struct PartKind {
  const char* format;
  int version;
  const char* run_function;
  const char* format_function;
};

struct Envelope {
  ShardId shard;
  std::string study;
  std::uint64_t fingerprint = 0;  // as stored
  nlohmann::json header, jobs;
};

std::string format_envelope(const PartKind& kind, const ShardId& shard, const std::string& study, std::uint64_t fingerprint,
                            const nlohmann::json& header, const nlohmann::json& jobs);

// Reads the envelope and checks the checksum. Throws InputError naming `source` when it is no part
// of this kind (or another version); ShardSetError (naming the shard, to be run again) once the
// shard is known: a file cut short, a damaged entry, a checksum that does not match.
Envelope parse_envelope(const std::string& text, const std::string& source, const PartKind& kind);

// Reads a part's members; fail() refuses the part. Once the envelope is read (`envelope` set), the
// refusal is a ShardSetError naming the shard to run again.
struct PartReader {
  const std::string& source;
  const PartKind& kind;
  const Envelope* envelope = nullptr;

  [[noreturn]] void fail(const std::string& what) const;
  const nlohmann::json& at(const nlohmann::json& j, const char* key, const std::string& path) const;
  double number(const nlohmann::json& j, const std::string& what) const;
  double number(const nlohmann::json& j, const char* key, const std::string& path) const;
  std::vector<double> numbers(const nlohmann::json& j, const char* key, const std::string& path) const;
  std::uint64_t hash(const nlohmann::json& j, const char* key, const std::string& path) const;  // "%016x"
  template <class T>
  T get(const nlohmann::json& j, const char* key, const std::string& path) const {
    try {
      return at(j, key, path).get<T>();
    } catch (const nlohmann::json::exception&) {
      fail("'" + path + key + "' has the wrong type");
    }
  }
};

}  // namespace toolpoint::part_file

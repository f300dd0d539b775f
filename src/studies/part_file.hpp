// toolpoint (internal): studies split into shards for a batch engine, and their part files — the one
// mechanism behind `plan --shard I/N` / `plan merge` (studies/plan.hpp) and the simulated stability
// map's `--shard` / merge (studies/simulation.hpp).
//
// A sharded study is a list of independent jobs; shard I of N computes the jobs j with j mod N = I.
// Its part file is JSON: a format name and version, the run's fingerprint (a hash of everything the
// results depend on, so parts of different runs are never merged), the shard, the study's header
// (its options, every double in C99 hexadecimal so that reading gives the same bits), the jobs and
// a checksum over the jobs' text (an edited or damaged part is refused). Merging checks that the
// parts are of one run, one split, every shard once and every job once, and then assembles exactly
// what the unsharded run gives.
#pragma once

#include <bit>
#include <cstddef>
#include <cstdint>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

namespace toolpoint::parts {

// ---- Shards --------------------------------------------------------------------------------------

// Throws InvalidArgument unless 1 ≤ count ≤ 100000 and 0 ≤ index < count.
void check_shard(int index, int count);

// The jobs of shard `index` of `count` among `jobs`: j with j mod count = index, in order.
std::vector<std::size_t> shard_jobs(std::size_t jobs, int index, int count);

// Which run and shard a part holds.
struct Origin {
  std::uint64_t fingerprint = 0;
  int index = 0, count = 1;
  std::vector<std::size_t> jobs;  // the job indices it holds
};

// The origins of a set of parts (each with header.fingerprint, index, count): `jobs_of(part)` its
// jobs, `index_of(job)` each job's index in the run.
template <class Part, class Jobs, class Index>
std::vector<Origin> origins_of(const std::vector<Part>& parts, Jobs jobs_of, Index index_of) {
  std::vector<Origin> out;
  for (const Part& p : parts) {
    Origin o{p.header.fingerprint, p.index, p.count, {}};
    for (const auto& job : jobs_of(p)) o.jobs.push_back(index_of(job));
    out.push_back(std::move(o));
  }
  return out;
}

// Checks a set of parts before they are merged into `jobs` jobs. Throws InvalidArgument when there
// are none, InputError naming the parts' sources when they belong to different runs (what: "plans",
// "simulated maps"), disagree on the shard count, hold a shard index outside 0…N−1 or a shard twice,
// miss a shard, hold a job outside the run or outside their shard (or twice), or leave a job out.
// `rerun` names the call that computes a missing shard, for the fix line.
void check_origins(const std::vector<Origin>& parts, const std::vector<std::string>& sources, std::size_t jobs,
                   const std::string& what, const std::string& rerun);

// ---- Hashing -------------------------------------------------------------------------------------

// 64-bit FNV-1a over the bits of every value fed in (doubles by their bit pattern).
struct Fnv1a {
  std::uint64_t h = 0xcbf29ce484222325ULL;
  void bytes(const void* p, std::size_t n) {
    const auto* c = static_cast<const unsigned char*>(p);
    for (std::size_t i = 0; i < n; ++i) h = (h ^ c[i]) * 0x100000001b3ULL;
  }
  void add(double x) {
    const auto b = std::bit_cast<std::uint64_t>(x);
    bytes(&b, sizeof b);
  }
  void add(std::uint64_t x) { bytes(&x, sizeof x); }
  void add(std::int64_t x) { bytes(&x, sizeof x); }
  void add(int x) { add(static_cast<std::int64_t>(x)); }
  void add(bool x) { add(static_cast<std::int64_t>(x)); }
  void add(const std::string& s) {
    add(static_cast<std::uint64_t>(s.size()));
    bytes(s.data(), s.size());
  }
  void add(const std::vector<double>& v) {
    add(static_cast<std::uint64_t>(v.size()));
    for (double x : v) add(x);
  }
};

// ---- Part files ----------------------------------------------------------------------------------

// A double as C99 hexadecimal text ("0x1.8p+1"; "inf", "-inf", "nan"): exact.
std::string hex(double x);
nlohmann::json hexes(const std::vector<double>& v);

// Reads a part's JSON, every failure an InputError naming `source` and the entry.
struct Reader {
  const std::string& source;
  std::string what = "part";  // "a plan part", for the fix line

  [[noreturn]] void fail(const std::string& message) const;
  const nlohmann::json& at(const nlohmann::json& j, const char* key, const std::string& path) const;
  double number(const nlohmann::json& j, const std::string& name) const;  // from hex()
  double number(const nlohmann::json& j, const char* key, const std::string& path) const;
  std::vector<double> numbers(const nlohmann::json& j, const char* key, const std::string& path) const;
  std::uint64_t hash(const nlohmann::json& j, const char* key, const std::string& path) const;  // 16 hex digits
  template <class T>
  T get(const nlohmann::json& j, const char* key, const std::string& path) const {
    try {
      return at(j, key, path).get<T>();
    } catch (const nlohmann::json::exception&) {
      fail("'" + path + key + "' has the wrong type");
    }
  }
};

// The text of a part file: {"format", "version", "fingerprint", "shard": {index, count}, "header",
// "checksum", "jobs"}.
std::string format_part(const std::string& format, int version, std::uint64_t fingerprint, int index, int count,
                        nlohmann::json header, nlohmann::json jobs);

// A part file read back: its format and version checked, its jobs against the checksum. The header
// is the caller's to read, and to check against `fingerprint` (which the caller recomputes).
struct Part {
  nlohmann::json header, jobs;
  std::uint64_t fingerprint = 0;
  int index = 0, count = 1;
};
// Throws InputError naming `source`: not JSON, another format (`what`: "a plan part"), another
// version, a damaged entry, jobs that do not match the checksum. `writer` names the function that
// writes such parts, for the fix line.
Part parse_part(const std::string& text, const std::string& source, const std::string& format, int version,
                const std::string& what, const std::string& writer);

}  // namespace toolpoint::parts

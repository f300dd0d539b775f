// toolpoint (internal): the part file of a sharded study (studies/shards.hpp) — the envelope every
// sharded study's parts share; the study brings its header and jobs as JSON (plan_io.cpp and
// simulation_io.cpp do), and its fingerprint (Fnv1a).
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

#include <bit>
#include <cstddef>
#include <cstdint>
#include <fmt/format.h>
#include <nlohmann/json.hpp>
#include <string>
#include <type_traits>
#include <vector>

#include "toolpoint/error.hpp"
#include "toolpoint/io/io.hpp"
#include "toolpoint/json.hpp"
#include "toolpoint/option_fields.hpp"
#include "toolpoint/studies/shards.hpp"

namespace toolpoint::part_file {

std::string hex(double x);
nlohmann::json hexes(const std::vector<double>& v);

// 64-bit FNV-1a over the bits of every value fed in (doubles by their bit pattern): a study's
// fingerprint is one of these over everything its results depend on.
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

// FNV-1a (64-bit) of text: the bytes alone (no length), as the checksum over the jobs.
std::uint64_t text_hash(const std::string& text);

// A double as exact JSON (hex()): what toolpoint::fields_json (json.hpp) writes an options
// table's reals with in a part file.
inline nlohmann::json hex_json(double x) { return hex(x); }

// The fingerprint's share of an options table: every field's value, in the table's order (a field
// added to the table changes every fingerprint, as it changes the study).
template <class Options>
void add_fields(Fnv1a& f, const std::vector<OptionField<Options>>& fields, const Options& o) {
  for (const OptionField<Options>& field : fields) f.add(field.get(o));
}

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

// Reads an options table's fields written by fields_json(…, hex_json) from `j` (at `path`, e.g. "options.lobes.")
// into `o`; a key missing or of the wrong type refuses the part.
template <class Options>
void read_fields(const PartReader& r, const nlohmann::json& j, const std::string& path,
                 const std::vector<OptionField<Options>>& fields, Options& o) {
  for (const OptionField<Options>& f : fields) switch (f.spec.kind) {
      case FieldKind::Real: f.set(o, r.number(j, f.spec.name, path)); break;
      case FieldKind::Integer: f.set(o, r.get<int>(j, f.spec.name, path)); break;
      case FieldKind::Flag: f.set(o, r.get<bool>(j, f.spec.name, path) ? 1.0 : 0.0); break;
    }
}

// A study's part in memory (PlanPart, SimulatedMapPart) has its header (with its fingerprint), its
// shard as index and count, and its study; label_of says what check_shard_set needs of it.
template <class Part>
PartLabel label_of(const Part& part, const std::string& source) {
  return {source, part.header.fingerprint, {part.index, part.count}, part.study};
}

// Reads a part file: the envelope (parse_envelope), the header (`parse_header(reader, json)`, whose
// fingerprint `fingerprint(header)` must be the stored one: an edited header is refused), the
// shard and study, then each job into `part.*jobs` (`parse_job(reader, json, "jobs[q].", header)`).
// Throws as parse_envelope, and ShardSetError through the reader for a header or job that is wrong.
template <class Part, class Job, class ParseHeader, class Fingerprint, class ParseJob>
Part parse_part(const std::string& text, const std::string& source, const PartKind& kind, std::vector<Job> Part::*jobs,
                ParseHeader parse_header, Fingerprint fingerprint, ParseJob parse_job) {
  const Envelope e = parse_envelope(text, source, kind);
  const PartReader r{source, kind, &e};
  Part part;
  part.header = parse_header(r, e.header);
  part.header.fingerprint = fingerprint(part.header);
  if (part.header.fingerprint != e.fingerprint)
    r.fail(fmt::format("the header does not match its fingerprint ({:016x}, computed {:016x}): edited or damaged", e.fingerprint,
                       part.header.fingerprint));
  part.index = e.shard.index;
  part.count = e.shard.count;
  part.study = e.study;
  for (std::size_t q = 0; q < e.jobs.size(); ++q)
    (part.*jobs).push_back(parse_job(r, e.jobs[q], fmt::format("jobs[{}].", q), part.header));
  return part;
}

// The jobs of a set of parts of one run, in the run's order (a study's merge). Refuses an empty set
// (InvalidArgument: "give every part file of the `whole`"), a set that is not one whole run
// (ShardSetError naming every problem, the shards to run again with `run_function`), and jobs
// outside their shard or held twice (check_jobs_placed). `jobs`: the run's job count (from the
// first part's header); `jobs_of(part)` a part's jobs; `index_of(job, source)` a job's index in the
// run (throwing InputError naming `source` for a job the run does not have). `sources` name the
// parts in messages ("part 2" where it has none).
template <class Part, class JobsOf, class IndexOf>
auto merged_jobs(const std::vector<Part>& parts, const std::vector<std::string>& sources, const std::string& whole,
                 const char* run_function, std::size_t jobs, JobsOf jobs_of, IndexOf index_of) {
  if (parts.empty()) throw InvalidArgument("no parts to merge", "give every part file of the " + whole);
  std::vector<PartLabel> labels;
  for (std::size_t p = 0; p < parts.size(); ++p)
    labels.push_back(label_of(parts[p], p < sources.size() ? sources[p] : "part " + std::to_string(p + 1)));
  throw_unless_whole(check_shard_set(labels), run_function);
  std::vector<std::vector<std::size_t>> held(parts.size());
  for (std::size_t p = 0; p < parts.size(); ++p)
    for (const auto& job : jobs_of(parts[p])) held[p].push_back(index_of(job, labels[p].source));
  check_jobs_placed(labels, held, jobs);
  std::vector<std::decay_t<decltype(jobs_of(parts.front()).front())>> out(jobs);
  for (std::size_t p = 0; p < parts.size(); ++p)
    for (std::size_t q = 0; q < held[p].size(); ++q) out[held[p][q]] = jobs_of(parts[p])[q];
  return out;
}

// Reads the part files of one run with `parse(text, path)` (a study's parse_*_part). A file that
// names its shard but cannot be used (cut short, damaged: ShardSetError) does not stop the reading:
// when there are any, the set's verdict over them and the readable parts is thrown at once
// (check_shard_set), so a merge names every problem in one go. Throws IoError (a file that cannot
// be read) and InputError (one that is no part of this kind) as they come.
template <class Part, class Parse>
std::vector<Part> read_part_files(const std::vector<std::string>& paths, const PartKind& kind, Parse parse) {
  std::vector<Part> parts;
  std::vector<std::string> names;
  std::vector<ShardSetCheck> unreadable;
  for (const std::string& path : paths) {
    try {
      parts.push_back(parse(read_text_file(path), path));
      names.push_back(path);
    } catch (const ShardSetError& e) {
      unreadable.push_back(e.check());
    }
  }
  if (!unreadable.empty()) {
    std::vector<PartLabel> labels;
    for (std::size_t p = 0; p < parts.size(); ++p) labels.push_back(label_of(parts[p], names[p]));
    throw ShardSetError(check_shard_set(labels, unreadable), kind.run_function);
  }
  return parts;
}

}  // namespace toolpoint::part_file

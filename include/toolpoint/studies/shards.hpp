// toolpoint study: a study split into shards for a batch engine (a Slurm job array, a Kubernetes
// Indexed Job) — what every sharded study shares, whatever its jobs are: the plan's set-ups
// (studies/plan.hpp) today, any other list of independent jobs (a simulated stability map's cells)
// the same way.
//
// A study of J independent jobs, numbered 0…J−1, is split into N shards. Shard I (0 ≤ I < N,
// counted from 0 like Slurm's `--array=0-(N-1)` and a Kubernetes Indexed Job's completion index)
// holds the jobs j with j mod N = I: round robin, so neighbouring jobs, which cost about the same,
// spread evenly. Each shard's result is a part; the parts of one run merge into the whole result
// once every shard is there exactly once. A shard's numbers do not depend on which process
// computed it, so a failed shard is simply run again, and only its part is rewritten.
//
// What a study brings: a fingerprint of everything its result depends on (parts of different
// studies are not merged), and per part its ShardId and its source (a file name, for messages).
// check_shard_set then says what is wrong with a set of parts as a whole — every missing shard,
// every repeated one, every part of another study or split — and ShardSetError carries that
// verdict so a front end can print the commands that mend it.
#pragma once

#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

#include "toolpoint/error.hpp"

namespace toolpoint {

inline constexpr int kMaxShards = 100000;

// Shard `index` of `count`.
struct ShardId {
  int index = 0;
  int count = 1;
};

// Throws InvalidArgument unless 1 ≤ count ≤ kMaxShards and 0 ≤ index < count, saying which: an
// index equal to the count is what an array numbered from 1 gives (Slurm's --array=1-N), and the
// message says so.
void check_shard(const ShardId& shard);

// Whether job j belongs to the shard (j mod count = index), and the shard's jobs of `jobs` in order.
bool in_shard(std::size_t job, const ShardId& shard);
std::vector<std::size_t> shard_jobs(std::size_t jobs, const ShardId& shard);

// What a merge knows of a part before its jobs: where it came from and which shard of which study.
struct PartLabel {
  std::string source;             // the file (for messages)
  std::uint64_t fingerprint = 0;  // of the study (its options and inputs)
  ShardId shard;
  // What the study was computed from, as its front end names it ("" unknown): the plan's study
  // file, a simulated map's command-line options; for the commands that redo a shard.
  std::string study;
};

// A shard to run again, and the part file it should write ("" when no part of the set says where).
struct ShardRerun {
  int index = 0;
  std::string part;
};

// The verdict on a set of parts. The run they belong to is the largest group of parts with one
// fingerprint and one shard count (the first part's group on a tie).
struct ShardSetCheck {
  std::uint64_t fingerprint = 0;      // of the run (0: unknown, a part cut short before it)
  int count = 0;                      // its shard count N
  std::string study;                  // its study file, from its parts ("" unknown)
  std::vector<ShardRerun> rerun;      // shards no usable part holds, by index
  std::vector<std::string> drop;      // parts to leave out: of another study or split, or a second copy of a shard
  std::vector<std::string> problems;  // one sentence per problem, naming the parts and shards
  bool ok() const { return rerun.empty() && drop.empty(); }
};

// Checks a set of parts as a whole; never throws. `unreadable`: the verdicts on parts that could
// not be read (the ShardSetError each threw: a file cut short, a damaged entry); their shards are
// to be run again into the same files, unless another part holds them. A missing shard's part file
// is named after a part of the set whose file name holds its own index (parts/part-3.json →
// parts/part-5.json).
ShardSetCheck check_shard_set(const std::vector<PartLabel>& parts, const std::vector<ShardSetCheck>& unreadable = {});

// The part file of shard `index`, named like `sibling`, the part of shard `sibling_index`: the last
// run of digits in its file name equal to sibling_index replaced by index; "" when it has none.
std::string sibling_part_path(const std::string& sibling, int sibling_index, int index);

// A set of parts that does not make one whole run, or a part that cannot be used (cut short,
// damaged): what() names every problem, hint() says which shards to run again (with `run_function`,
// e.g. "run_plan_part") and which parts to drop; check() holds the same for a front end to turn
// into its own commands.
class ShardSetError : public InputError {
 public:
  ShardSetError(ShardSetCheck check, const std::string& run_function);
  const ShardSetCheck& check() const noexcept { return check_; }

 private:
  ShardSetCheck check_;
};

// Throws ShardSetError unless check.ok().
void throw_unless_whole(const ShardSetCheck& check, const std::string& run_function);

// Where the jobs of a set of parts go, once check_shard_set has passed: `jobs_of[p]` are the job
// indices parts[p] holds. Throws InputError naming the part when one of them lies outside the run's
// `jobs`, outside the part's shard or is held twice, and naming a job no part holds: a part whose
// checksum holds but whose jobs are wrong was written wrongly or edited, and its shard is run again.
void check_jobs_placed(const std::vector<PartLabel>& parts, const std::vector<std::vector<std::size_t>>& jobs_of,
                       std::size_t jobs);

// "3, 5, 7" (indices in order, runs of 4 or more as "8-15").
std::string shard_list(const std::vector<int>& indices);

}  // namespace toolpoint

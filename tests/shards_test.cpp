// Shards of a study and the verdict on a set of parts (studies/shards.hpp), on labels made by hand:
// the oracle is the set as built here (which shards are there, twice, of another study or split).
#include <gtest/gtest.h>

#include <numeric>
#include <string>
#include <vector>

#include "toolpoint/error.hpp"
#include "toolpoint/studies/shards.hpp"

using namespace toolpoint;

namespace {

PartLabel label(const std::string& source, int index, int count = 4, std::uint64_t fingerprint = 7) {
  return {source, fingerprint, {index, count}, "study.toml"};
}

}  // namespace

// Round robin: every job in exactly one shard, shard I holding j ≡ I (mod N).
TEST(Shards, EveryJobInExactlyOneShard) {
  for (int count : {1, 3, 7, 20}) {
    std::vector<int> seen(17, 0);
    for (int i = 0; i < count; ++i)
      for (std::size_t j : shard_jobs(17, {i, count})) {
        EXPECT_EQ(static_cast<int>(j % static_cast<std::size_t>(count)), i);
        EXPECT_TRUE(in_shard(j, {i, count}));
        ++seen[j];
      }
    EXPECT_EQ(std::accumulate(seen.begin(), seen.end(), 0), 17) << count;
    EXPECT_EQ(*std::min_element(seen.begin(), seen.end()), 1) << count;
  }
}

TEST(Shards, AShardThatDoesNotExistSaysWhy) {
  EXPECT_NO_THROW(check_shard({0, 1}));
  EXPECT_NO_THROW(check_shard({99999, 100000}));
  try {
    check_shard({16, 16});
    ADD_FAILURE();
  } catch (const InvalidArgument& e) {
    EXPECT_NE(std::string(e.what()).find("counted from 0, the last is 15"), std::string::npos) << e.what();
    EXPECT_NE(std::string(e.what()).find("numbered from 1"), std::string::npos) << e.what();
    EXPECT_NE(e.hint().find("0-15"), std::string::npos) << e.hint();
  }
  EXPECT_THROW(check_shard({17, 16}), InvalidArgument);
  EXPECT_THROW(check_shard({-1, 16}), InvalidArgument);
  EXPECT_THROW(check_shard({0, 100001}), InvalidArgument);
}

TEST(Shards, ListsAndSiblingNames) {
  EXPECT_EQ(shard_list({5, 3, 8, 9, 10, 11, 3, 1}), "1, 3, 5, 8-11");
  EXPECT_EQ(shard_list({0, 1, 2}), "0, 1, 2");
  EXPECT_EQ(sibling_part_path("parts/part-3.json", 3, 12), "parts/part-12.json");
  EXPECT_EQ(sibling_part_path("run7/part-03.json", 3, 5), "run7/part-05.json");  // the folder's digits left alone
  EXPECT_EQ(sibling_part_path("p12_of_16.json", 12, 4), "p4_of_16.json");
  EXPECT_EQ(sibling_part_path("plan-part.json", 3, 4), "");
}

TEST(Shards, AWholeSetPasses) {
  const ShardSetCheck c = check_shard_set(
      {label("p/part-2.json", 2), label("p/part-0.json", 0), label("p/part-3.json", 3), label("p/part-1.json", 1)});
  EXPECT_TRUE(c.ok());
  EXPECT_TRUE(c.problems.empty());
  EXPECT_EQ(c.count, 4);
  EXPECT_NO_THROW(throw_unless_whole(c, "run_x_part"));
}

// The run is the largest group (one fingerprint, one count); the rest is named and left out, the
// shards it lacks run again into files named like their siblings.
TEST(Shards, EveryProblemOfASetAtOnce) {
  const ShardSetCheck c = check_shard_set({label("other/o-1.json", 1, 4, 9), label("p/part-0.json", 0), label("p/part-2.json", 2),
                                           label("p/part-2-copy.json", 2), label("q/part-1.json", 1, 3)});
  EXPECT_FALSE(c.ok());
  EXPECT_EQ(c.fingerprint, 7u);
  EXPECT_EQ(c.count, 4);
  EXPECT_EQ(c.drop, (std::vector<std::string>{"other/o-1.json", "p/part-2-copy.json", "q/part-1.json"}));
  ASSERT_EQ(c.rerun.size(), 2u);
  EXPECT_EQ(c.rerun[0].index, 1);
  EXPECT_EQ(c.rerun[0].part, "p/part-1.json");
  EXPECT_EQ(c.rerun[1].index, 3);
  EXPECT_EQ(c.rerun[1].part, "p/part-3.json");
  try {
    throw_unless_whole(c, "run_x_part");
    ADD_FAILURE();
  } catch (const ShardSetError& e) {
    const std::string what = e.what();
    for (const char* m :
         {"not one whole run of 4 shards", "other/o-1.json (shard 1 of 4) belongs to another study",
          "shard 2 of 4 is given 2 times: p/part-2.json and p/part-2-copy.json",
          "q/part-1.json is shard 1 of 3, but the other parts split the study into 4", "shard(s) 1, 3 of 4 missing"})
      EXPECT_NE(what.find(m), std::string::npos) << m << "\n" << what;
    EXPECT_NE(e.hint().find("leave out other/o-1.json, p/part-2-copy.json, q/part-1.json"), std::string::npos) << e.hint();
    EXPECT_NE(e.hint().find("run shard(s) 1, 3 of 4 again (run_x_part"), std::string::npos) << e.hint();
    EXPECT_EQ(e.check().rerun.size(), 2u);
  }
}

// An unreadable part (cut short) is run again into its own file; one whose shard a good part holds is
// left out instead; one cut before its fingerprint counts for the run of its split.
TEST(Shards, UnreadablePartsAreRunAgainIntoTheirFiles) {
  ShardSetCheck cut;
  cut.count = 4;
  cut.fingerprint = 0;
  cut.rerun = {{3, "p/part-3.json"}};
  cut.problems = {"p/part-3.json (shard 3 of 4): cut short"};
  ShardSetCheck c = check_shard_set({label("p/part-0.json", 0), label("p/part-1.json", 1), label("p/part-2.json", 2)}, {cut});
  ASSERT_EQ(c.rerun.size(), 1u);
  EXPECT_EQ(c.rerun[0].part, "p/part-3.json");
  EXPECT_TRUE(c.drop.empty());
  EXPECT_EQ(c.problems, std::vector<std::string>{"p/part-3.json (shard 3 of 4): cut short"});
  cut.rerun = {{2, "old/part-2.json"}};
  c = check_shard_set({label("p/part-0.json", 0), label("p/part-1.json", 1), label("p/part-2.json", 2)}, {cut});
  EXPECT_EQ(c.drop, std::vector<std::string>{"old/part-2.json"});
  ASSERT_EQ(c.rerun.size(), 1u);
  EXPECT_EQ(c.rerun[0].part, "p/part-3.json");
}

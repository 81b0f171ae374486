// Which controller node answered for which robots: overlaps, gaps and ranges beyond the swarm.
#include <gtest/gtest.h>

#include "swarm_forage/core/run/range_coverage.hpp"

namespace swarm_forage {
namespace {

using Added = RangeCoverage::Added;
bool contains(const std::string& s, const std::string& part) { return s.find(part) != std::string::npos; }

TEST(RangeCoverage, SplitAcrossNodesCompletesTheTick) {
  RangeCoverage c("swarm/commands");
  c.begin(64);
  EXPECT_EQ(c.add(0, 32, "/a"), Added::kNew);
  EXPECT_FALSE(c.complete());
  EXPECT_EQ(c.add(32, 32, "/b"), Added::kNew);
  EXPECT_TRUE(c.complete());
  EXPECT_EQ(c.senders(), 2u);
  EXPECT_EQ(c.add(0, 32, "/a"), Added::kRepeat);  // a re-offered tick answered again
}

TEST(RangeCoverage, OverlapNamesBothNodesAndTheIds) {
  RangeCoverage c("swarm/commands");
  c.begin(64);
  EXPECT_EQ(c.add(0, 64, "/controller"), Added::kNew);
  EXPECT_EQ(c.add(32, 32, "/controller_upper"), Added::kRejected);
  const std::string both =
      "robots [32, 64) on swarm/commands are claimed by both /controller ([0, 64)) and "
      "/controller_upper ([32, 64))";
  EXPECT_TRUE(contains(c.rejection(), both)) << c.rejection();
  c.begin(64);  // the other order of arrival: the same words
  EXPECT_EQ(c.add(32, 32, "/controller_upper"), Added::kNew);
  EXPECT_EQ(c.add(0, 64, "/controller"), Added::kRejected);
  EXPECT_TRUE(contains(c.rejection(), both)) << c.rejection();
  c.begin(64);
  EXPECT_EQ(c.add(0, 40, "/a"), Added::kNew);
  EXPECT_EQ(c.add(30, 34, "/b"), Added::kRejected);
  EXPECT_TRUE(contains(c.rejection(),
                       "robots [30, 40) on swarm/commands are claimed by both /a ([0, 40)) and "
                       "/b ([30, 64))"))
      << c.rejection();
  EXPECT_EQ(c.add(60, 10, "/c"), Added::kRejected);
  EXPECT_TRUE(contains(c.rejection(), "beyond the swarm of 64")) << c.rejection();
}

TEST(RangeCoverage, GapAndSilentNodeAreNamed) {
  RangeCoverage c("swarm/commands");
  c.begin(64);
  EXPECT_TRUE(contains(c.missing(), "robots [0, 64) on swarm/commands (no node has answered at all)"))
      << c.missing();
  c.add(0, 30, "/a");
  c.add(32, 32, "/b");
  EXPECT_EQ(c.missing(),
            "robots [30, 32) on swarm/commands: no node serves them (/a serves [0, 30), /b serves [32, 64))");
  c.begin(64);  // next tick: /b has gone silent
  c.add(0, 30, "/a");
  EXPECT_TRUE(contains(c.missing(), "robots [30, 64) on swarm/commands from /b")) << c.missing();
}

}  // namespace
}  // namespace swarm_forage

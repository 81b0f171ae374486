// Measured conditions (waveform series): the file's format, its interpolation and holds, the refusal of a
// malformed file naming the file and the line, and the identity by content (docs/design-model.md,
// Environmental condition). Also the target's part in labels, tags and identities.
#include <gtest/gtest.h>

#include <cstdio>
#include <fstream>
#include <string>

#include "swarm_forage/core/metrics/run_library.hpp"
#include "swarm_forage/core/run/condition.hpp"
#include "swarm_forage/core/world/config.hpp"

namespace swarm_forage {
namespace {

/// A file of `text` in the test's temporary folder, removed with the object.
struct TempFile {
  std::string path;
  TempFile(const std::string& name, const std::string& text) : path(testing::TempDir() + name) {
    std::ofstream(path) << text;
  }
  ~TempFile() { std::remove(path.c_str()); }
};

Condition series(const std::string& path, const std::string& target = "carry_speed") {
  Condition c;
  c.waveform = "series";
  c.series = path;
  c.target = target;
  return c.forRun(1000, 5.0);
}

std::string parseError(const std::string& text) {
  try {
    ConditionSeries::parse(text, "p.csv");
  } catch (const ParameterError& e) {
    return e.what();
  }
  ADD_FAILURE() << "accepted: " << text;
  return {};
}

std::string identity(const Condition& c) {
  RunKey k;
  k.controller = "crw";
  k.arena = "32x16";
  k.swarm_size = 4;
  k.environment = c;
  return k.identity();
}

TEST(ConditionSeries, InterpolatesLinearlyAndHoldsTheEnds) {
  const auto s = ConditionSeries::parse("t,V\n# a comment\n10, 0.0\n\n20 0.5\n40\t-0.5\n", "p.csv");
  ASSERT_EQ(s->t.size(), 3u);
  EXPECT_DOUBLE_EQ(s->at(0.0), 0.0);  // before the first time: the first V
  EXPECT_DOUBLE_EQ(s->at(10.0), 0.0);
  EXPECT_DOUBLE_EQ(s->at(15.0), 0.25);  // linear between rows
  EXPECT_DOUBLE_EQ(s->at(20.0), 0.5);
  EXPECT_DOUBLE_EQ(s->at(30.0), 0.0);
  EXPECT_DOUBLE_EQ(s->at(40.0), -0.5);
  EXPECT_DOUBLE_EQ(s->at(1e9), -0.5);  // after the last time: the last V
  EXPECT_DOUBLE_EQ(ConditionSeries::parse("5,0.3\n", "one.csv")->at(0), 0.3);  // one row: constant
}

TEST(ConditionSeries, MalformedFilesNameTheFileAndTheLine) {
  EXPECT_NE(parseError("t,V\n0,0\n1,0.5,2\n").find("series file 'p.csv' line 3"), std::string::npos);
  EXPECT_NE(parseError("t,V\n0,0\n1,x\n").find("line 3"), std::string::npos);
  EXPECT_NE(parseError("0,0\n1,1.5\n").find("line 2: V 1.5 is not within [-1, 1]"), std::string::npos);
  EXPECT_NE(parseError("0,0\n# c\n0,0.2\n").find("line 3: t 0 s does not increase"), std::string::npos);
  EXPECT_NE(parseError("0,0\n2,0\n1,0\n").find("line 3"), std::string::npos);
  EXPECT_NE(parseError("0,0\n1,nan\n").find("line 2"), std::string::npos);
  EXPECT_NE(parseError("0,0\ninf,0\n").find("not finite"), std::string::npos);
  EXPECT_NE(parseError("t,V\n").find("line 2: the file ends without a row"), std::string::npos);
  EXPECT_NE(parseError("").find("without a row"), std::string::npos);
  EXPECT_NE(parseError("t,V\ntime,value\n").find("line 2"), std::string::npos);  // one header only
  // Only the documented header is skipped: a mistyped first row is an error naming the field.
  EXPECT_NE(parseError("1O,0.9\n20,0.5\n")
                .find("line 1: '1O,0.9' is not two numbers t, V: field 1 '1O' is not "
                      "a number"),
            std::string::npos);
  EXPECT_NE(parseError("# c\n10,O.5\n").find("line 2: '10,O.5' is not two numbers t, V: field 2 'O.5'"),
            std::string::npos);
  EXPECT_NE(parseError("time,value\n0,0\n").find("line 1"), std::string::npos);
  EXPECT_NE(parseError("t,V,x\n0,0\n").find("line 1"), std::string::npos);
  EXPECT_EQ(ConditionSeries::parse("T,v\n0,0.2\n", "p.csv")->t.size(), 1u);
  EXPECT_EQ(ConditionSeries::parse("\xEF\xBB\xBFt,V\n0,0.2\n", "bom.csv")->v.at(0), 0.2);
  try {
    series(testing::TempDir());
    ADD_FAILURE() << "a directory was read as a series";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("' is a directory; valid: a CSV file"), std::string::npos)
        << e.what();
  }
  try {
    series(testing::TempDir() + "no_such_profile.csv");
    ADD_FAILURE() << "a missing file was accepted";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("no_such_profile.csv' cannot be read"), std::string::npos);
  }
}

TEST(ConditionSeries, ConditionReadsTheFileAndItsContentIsTheIdentity) {
  const TempFile a("profile_a.csv", "t,V\n0,0\n100,0.8\n");
  const TempFile same("profile_b.csv", "t,V\n0,0\n100,0.8\n");
  const TempFile changed("profile_c.csv", "t,V\n0,0\n100,0.7\n");
  const Condition c = series(a.path);
  EXPECT_DOUBLE_EQ(c.value(50.0), 0.4);
  EXPECT_DOUBLE_EQ(c.value(1000.0), 0.8);
  EXPECT_EQ(c.series_digest.size(), 16u);
  EXPECT_FALSE(c.ideal());
  EXPECT_EQ(identity(c), identity(series(same.path))) << "the same content under another path";
  EXPECT_TRUE(c == series(same.path));
  EXPECT_NE(identity(c), identity(series(changed.path)));
  EXPECT_NE(c.tag(), series(changed.path).tag());
  EXPECT_EQ(c.tag(), "series-" + c.series_digest.substr(0, 8));
  EXPECT_EQ(c.label(), "series profile_a.csv #" + c.series_digest.substr(0, 8));
  EXPECT_EQ(c.normalized().series_digest, c.series_digest);
  EXPECT_EQ(identity(c), identity(c.normalized()));
  // A series without a file is refused by name.
  Condition none;
  none.waveform = "series";
  EXPECT_THROW(none.forRun(1000, 5.0), ParameterError);
}

TEST(ConditionTarget, LabelTagAndIdentityChangeOnlyOffTheDefault) {
  Condition c;
  c.waveform = "constant";
  c.beta = 0.4;
  Condition speed = c, manip = c;
  speed.target = "speed";
  manip.target = "manipulation_time";
  EXPECT_EQ(c.tag(), "constant0.4");
  EXPECT_EQ(speed.tag(), "constant0.4-speed");
  EXPECT_EQ(manip.label(), "constant beta=0.4 target=manipulation_time");
  EXPECT_NE(identity(c), identity(speed));
  EXPECT_NE(identity(speed), identity(manip));
  RunKey k;
  k.environment = c;
  EXPECT_EQ(k.describe().find("target"), std::string::npos) << "the default's identity text is as before";
  EXPECT_EQ(c.throttling(0.3).target, ConditionTarget::kCarrySpeed);
  EXPECT_EQ(manip.throttling(0.3).target, ConditionTarget::kManipulationTime);
  // With V = 0 throughout no target acts: one null run.
  Condition idle = speed;
  idle.beta = 0;
  EXPECT_EQ(idle.normalized().tag(), "null");
  Condition bad = c;
  bad.target = "pickup";
  try {
    bad.validate();
    ADD_FAILURE() << "target pickup accepted";
  } catch (const ParameterError& e) {
    EXPECT_NE(std::string(e.what()).find("valid: carry_speed, speed, manipulation_time"), std::string::npos);
  }
}

}  // namespace
}  // namespace swarm_forage

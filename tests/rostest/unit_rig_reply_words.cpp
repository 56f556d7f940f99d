// The words of rig answers that other nodes act on (rig_reply_words.h):
// what AxisArbiter refuses about the caller reads as an owner refusal, and
// nothing else it refuses does (a release refused for another reason must
// not count as done); the servo's pending ~enable answer reads as "not
// claimed yet"; the Python nodes' copies (scripts/rig_service_calls.py)
// give the same words, asked of Debian's Python (the nodes' #!/usr/bin/python3).
#include <string>

#include <gtest/gtest.h>

#include "support/script_run.h"
#include "virtual_triaxial/ros/axis_arbiter.h"
#include "virtual_triaxial/ros/rig_reply_words.h"

namespace words = vt::ros::reply_words;
using vt::ros::AxisArbiter;

TEST(RigReplyWords, TheArbitersRefusalsAboutTheCallerAndOnlyThoseAreOwnerRefusals) {
  AxisArbiter a;
  a.set_limit(1e-6, 1e-3);
  EXPECT_TRUE(words::is_owner_refusal(a.claim("", {0}, 0)));
  EXPECT_TRUE(words::is_owner_refusal(a.release("", {0})));
  EXPECT_TRUE(words::is_owner_refusal(a.release("nobody", {0})));
  EXPECT_TRUE(words::is_owner_refusal(a.command("nobody", 0, {0}, {0.0}, 0, true)));
  ASSERT_EQ(a.claim("servo", {0, 1}, 0), "");
  // refusals about axes, rates and ticks are not
  for (const std::string& refusal : {a.claim("other", {1}, 0), a.release("servo", {2}),
                                     a.command("servo", 3, {0}, {0.0}, 0, true), a.set_open_loop_rate(0, 0.0)}) {
    EXPECT_NE(refusal, "") << "the request must be refused";
    EXPECT_FALSE(words::is_owner_refusal(refusal)) << refusal;
  }
  EXPECT_FALSE(words::is_owner_refusal(""));
}

TEST(RigReplyWords, APendingEnableSaysNotClaimedYetAndNamesWhy) {
  const std::string m = words::enabled_not_claimed_yet("claim_axes: dem_node does not answer");
  EXPECT_TRUE(words::says_not_claimed_yet(m)) << m;
  EXPECT_NE(m.find("claim_axes: dem_node does not answer"), std::string::npos) << m;
  EXPECT_EQ(m.rfind("enabled; ", 0), 0u) << m;
  EXPECT_FALSE(words::says_not_claimed_yet("enabled; axes [0, 1] claimed"));
  EXPECT_FALSE(words::says_not_claimed_yet("already enabled; axes [0, 1] claimed"));
}

TEST(RigReplyWords, ThePythonNodesUseTheSameWords) {
  // rospy (which the module imports and uses only in its calls) is an
  // empty module here, so only the words can fail; the scripts folder
  // comes as an argument
  const std::string out = vt::test::run(
      "/usr/bin/python3 -B -c \"import sys, types; sys.path.insert(0, sys.argv[1]); "
      "sys.modules.setdefault('rospy', types.ModuleType('rospy')); import rig_service_calls as r; "
      "print(r.OWNER_REFUSAL); print(r.NOT_CLAIMED_YET); print(r.enabled_not_claimed_yet('why (x)'))\" "
      "\"" VT_SOURCE_DIR "/scripts\" 2>&1");
  const std::string expected = std::string(words::kOwnerRefusal) + "\n" + words::kNotClaimedYet + "\n" +
                               words::enabled_not_claimed_yet("why (x)") + "\n";
  EXPECT_EQ(out, expected);
}

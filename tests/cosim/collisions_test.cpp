// SUMO's collisions: one count per contact, and SUMO's --collision-output file read back (the
// source over libtraci, whose getCollisions SUMO 1.15 leaves unimplemented). The end-to-end check
// against libsumo's getCollisions is in gui_test.cpp.
#include <gtest/gtest.h>

#include <fstream>

#include "test_util.hpp"
#include <stcosim/collisions.hpp>

namespace st::cosim {
namespace {

using namespace st::cosim::test;

SumoCollision report(double t, const std::string& collider, const std::string& victim) {
  SumoCollision c;
  c.time = t;
  c.collider = collider;
  c.victim = victim;
  return c;
}

TEST(Collisions, OnePerContactWhateverTheOrderOfThePair) {
  CollisionCounter n;
  n.step({report(1.0, "a", "b")});
  n.step({report(1.1, "b", "a"), report(1.1, "c", "d")});  // still touching; a new pair
  n.step({});                                               // both apart
  n.step({report(1.3, "a", "b")});                          // a second collision of a and b
  EXPECT_EQ(n.distinct(), 3u);
  EXPECT_EQ(n.reports(), 4u);
}

TEST(Collisions, ReplayedReportsSeeTheStepsWithoutReports) {
  const std::vector<SumoCollision> reports = {report(1.0, "a", "b"), report(1.1, "a", "b"), report(1.1, "c", "d"),
                                              report(1.3, "a", "b"), report(1.4, "a", "b"), report(1.4, "c", "d")};
  CollisionCounter n;
  countCollisions(n, reports, 0.1);
  // a-b: 1.0-1.1 and again from 1.3 (1.2 had no report); c-d: 1.1 and again at 1.4
  EXPECT_EQ(n.distinct(), 4u);
  EXPECT_EQ(n.reports(), 6u);
  // 2.0 and 2.2: consecutive steps of 0.2 s (one contact), a step apart with 0.1 s steps (two)
  const std::vector<SumoCollision> twoReports = {report(2.0, "a", "b"), report(2.2, "a", "b")};
  CollisionCounter coarse, fine;
  countCollisions(coarse, twoReports, 0.2);
  countCollisions(fine, twoReports, 0.1);
  EXPECT_EQ(coarse.distinct(), 1u);
  EXPECT_EQ(fine.distinct(), 2u);
}

highway::Warning warning(const std::string& ego, const std::string& foe, double begin, double end,
                         highway::WarningKind kind = highway::WarningKind::Vehicle) {
  highway::Warning w;
  w.ego = ego;
  w.foe = foe;
  w.kind = kind;
  w.begin = begin;
  w.end = end;
  return w;
}

TEST(Collisions, LeadTimeIsTheCollidersWarningOnAtTheCollision) {
  const std::vector<SumoCollision> firsts = {report(10.0, "a", "b"), report(12.0, "c", "d"), report(12.0, "e", "f"),
                                             report(20.0, "g", "h"), report(30.0, "a", "b")};
  const std::vector<highway::Warning> warnings = {
      warning("a", "b", 7.0, 8.0),    // 0.5 s before the next: one warning from 7.0
      warning("a", "b", 8.5, 10.3),   // on at 10.0: lead 3.0
      warning("d", "c", 9.0, 12.5),   // the victim's warning: the collider was not warned
      warning("e", "f", 8.0, 9.0),    // over 3 s before: not warned
      warning("g", "h", 15.0, 20.0, highway::WarningKind::Curb),  // not about the victim
      warning("g", "h", 19.5, 19.95),  // ended one step (0.1 s) before the contact: still counts
      warning("a", "b", 25.0, 26.0), warning("a", "b", 28.0, 30.0)};  // 2 s gap: from 28.0
  const auto w = collisionWarnings(firsts, 0.1, warnings);
  ASSERT_EQ(w.size(), 5u);
  ASSERT_TRUE(w[0].leadTime.has_value());
  EXPECT_DOUBLE_EQ(*w[0].leadTime, 3.0);
  EXPECT_FALSE(w[1].leadTime.has_value());
  EXPECT_FALSE(w[2].leadTime.has_value());
  ASSERT_TRUE(w[3].leadTime.has_value());
  EXPECT_DOUBLE_EQ(*w[3].leadTime, 0.5);
  ASSERT_TRUE(w[4].leadTime.has_value());
  EXPECT_DOUBLE_EQ(*w[4].leadTime, 2.0);
  EXPECT_EQ(w[4].collision.time, 30.0);
}

TEST(Collisions, ReadsSumosFileAndNamesWhatIsWrong) {
  const auto dir = freshDir("collision_output");
  std::ofstream(dir / "ok.xml")
      << "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n<collisions>\n"
         "    <collision time=\"210.30\" type=\"collision\" lane=\"downstream_2\" pos=\"1271.22\" collider=\"main2.39\" "
         "victim=\"ramp.17\" colliderType=\"car\" victimType=\"car\" colliderSpeed=\"25.95\" victimSpeed=\"23.57\"/>\n"
         "    <collision time=\"210.40\" type=\"frontal\" lane=\"x_0\" collider=\"a\" victim=\"b\" colliderType=\"t\" "
         "victimType=\"t\" colliderSpeed=\"1\" victimSpeed=\"0\"/>\n</collisions>\n";
  const auto all = readCollisionOutput(dir / "ok.xml", 0.1);  // SUMO's step-begin stamps + one step
  ASSERT_EQ(all.size(), 2u);
  EXPECT_DOUBLE_EQ(all[0].time, 210.3 + 0.1);
  EXPECT_EQ(all[0].collider, "main2.39");
  EXPECT_EQ(all[0].victim, "ramp.17");
  EXPECT_EQ(all[0].lane, "downstream_2");
  EXPECT_DOUBLE_EQ(all[0].pos, 1271.22);
  EXPECT_DOUBLE_EQ(all[0].colliderSpeed, 25.95);
  EXPECT_DOUBLE_EQ(all[0].victimSpeed, 23.57);
  EXPECT_EQ(all[1].type, "frontal");
  EXPECT_DOUBLE_EQ(all[1].pos, 0.0);  // pos is optional in SUMO's schema

  auto errorOf = [&](const std::string& name, const std::string& text) {
    std::ofstream(dir / name) << text;
    try {
      readCollisionOutput(dir / name, 0.1);
    } catch (const std::runtime_error& e) {
      return std::string(e.what());
    }
    return std::string();
  };
  std::string e = errorOf("cut.xml", "<collisions>\n<collision time=\"1\"\n");
  EXPECT_NE(e.find("cut.xml:2: unexpected end of file inside <collision>"), std::string::npos) << e;
  // a file SUMO did not close (killed mid-run) is not read as whole
  e = errorOf("open.xml", "<collisions>\n<collision time=\"1\" type=\"collision\" lane=\"l\" collider=\"a\" victim=\"b\" "
                          "colliderSpeed=\"1\" victimSpeed=\"1\"/>\n");
  EXPECT_NE(e.find("open.xml:3: unexpected end of file: <collisions> (line 1) is not closed"), std::string::npos) << e;
  e = errorOf("noid.xml", "<collisions><collision time=\"1\" type=\"collision\" lane=\"l\" victim=\"b\" "
                          "colliderSpeed=\"1\" victimSpeed=\"1\"/></collisions>");
  EXPECT_NE(e.find("noid.xml:1: a <collision> has no 'collider' attribute"), std::string::npos) << e;
  e = errorOf("nan.xml", "<collisions><collision time=\"soon\" type=\"collision\" lane=\"l\" collider=\"a\" "
                         "victim=\"b\" colliderSpeed=\"1\" victimSpeed=\"1\"/></collisions>");
  EXPECT_NE(e.find("nan.xml:1: <collision time=\"soon\">: not a number"), std::string::npos) << e;
  e = errorOf("other.xml", "<fcd-export/>");
  EXPECT_NE(e.find("other.xml: not a SUMO collision output"), std::string::npos) << e;
  EXPECT_NE(errorOf("absent.xml", "").find("absent.xml"), std::string::npos);
  std::filesystem::remove(dir / "absent.xml");
  try {
    readCollisionOutput(dir / "absent.xml", 0.1);
    ADD_FAILURE() << "a missing file must throw";
  } catch (const std::runtime_error& ex) {
    EXPECT_NE(std::string(ex.what()).find("absent.xml"), std::string::npos) << ex.what();
  }
}

}  // namespace
}  // namespace st::cosim

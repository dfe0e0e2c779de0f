// Persons and speed and separation monitoring (ISO/TS 15066 §5.5.4), against independent truth:
// S_p terms worked out by hand from formulae (1)-(4), verdict transitions of a person walking at
// constant speed towards a post at times solved from the geometry, person-arm separation against
// brute-force sampling, the reachable set against sampled motions, and the closed loop never
// letting a person touch a moving arm.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <sstream>

#include <stcore/distance.hpp>
#include <starm/study.hpp>

namespace st::arm {
namespace {

namespace fs = std::filesystem;

std::string scenarioPath(const std::string& name) {
  return std::string(STSIM_SOURCE_DIR) + "/models/arm/scenarios/" + name + ".yaml";
}

fs::path write(const std::string& name, const std::string& text) {
  const fs::path p = fs::temp_directory_path() / ("stsim_arm_ssm_" + std::to_string(::getpid()) + "_" + name);
  std::ofstream(p) << text;
  return p;
}

TEST(Ssm, TermsEqualTheStandardsFormulaeByHand) {
  // (a) the defaults: T_r = 0.011, T_s = 0.2, C = 0, Z_d = 0.05, Z_r = 0.01; walking, robot 1 m/s
  SsmConfig a;
  SeparationTerms t = protectiveSeparation(a, 1.6, 1.0);
  EXPECT_NEAR(t.sh, 0.3376, 1e-15);  // 1.6 * (0.011 + 0.2)
  EXPECT_NEAR(t.sr, 0.011, 1e-15);   // 1.0 * 0.011
  EXPECT_NEAR(t.ss, 0.1, 1e-15);     // 1.0 * 0.2 / 2
  EXPECT_NEAR(t.total(), 0.5086, 1e-15);
  EXPECT_STREQ(t.dominant(), "S_h");
  // (b) a slow drive: T_r = 0.1, T_s = 0.5, C = 0.2, Z_d = 0.1, Z_r = 0.02; a hand, robot 0.5 m/s
  SsmConfig b;
  b.reactionTime = 0.1;
  b.stoppingTime = 0.5;
  b.intrusion = 0.2;
  b.personUncertainty = 0.1;
  b.robotUncertainty = 0.02;
  t = protectiveSeparation(b, 2.0, 0.5);
  EXPECT_NEAR(t.sh, 1.2, 1e-15);     // 2.0 * 0.6
  EXPECT_NEAR(t.sr, 0.05, 1e-15);    // 0.5 * 0.1
  EXPECT_NEAR(t.ss, 0.125, 1e-15);   // 0.5 * 0.5 / 2
  EXPECT_NEAR(t.total(), 1.695, 1e-14);
  // (c) a light curtain's intrusion (ISO 13855, 850 mm), no uncertainties, a fast robot
  SsmConfig c;
  c.reactionTime = 0.05;
  c.stoppingTime = 0.3;
  c.intrusion = 0.85;
  c.personUncertainty = 0.0;
  c.robotUncertainty = 0.0;
  t = protectiveSeparation(c, 1.6, 2.0);
  EXPECT_NEAR(t.sh, 0.56, 1e-15);   // 1.6 * 0.35
  EXPECT_NEAR(t.sr, 0.1, 1e-15);    // 2.0 * 0.05
  EXPECT_NEAR(t.ss, 0.3, 1e-15);    // 2.0 * 0.3 / 2
  EXPECT_NEAR(t.total(), 1.81, 1e-14);
  EXPECT_STREQ(t.dominant(), "C");
  // the speed that keeps S_p at the next cycle, (a) at 0.8 m: room 0.8 - 1.6 * 0.001 - (0.3376 + 0.06),
  // per m/s 0.011 + 0.1 + 0.001
  EXPECT_NEAR(allowedRobotSpeed(a, 1.6, 0.8), 0.4008 / 0.112, 1e-12);
  // and at that speed S_p after one cycle of both closing is exactly the distance left
  const double v = allowedRobotSpeed(a, 1.6, 0.8);
  EXPECT_NEAR(protectiveSeparation(a, 1.6, v).total(), 0.8 - (1.6 + v) * 0.001, 1e-12);
  EXPECT_LT(allowedRobotSpeed(a, 2.0, 0.4), 0.0);  // within S_h + Z of a hand: no speed
}

TEST(Ssm, DrivenTermsAndSpeedsEqualTheFormulaeByHand) {
  // S_r = v_b T_r, S_s = v_b s_b T_s / 2 with v_b = max(s_b R, v_r + (s_b - s) R): the drive stops from
  // program speed s_b in s_b T_s. (a) the defaults (R = 1), scaled to s = s_b = 0.5, v_r = 0.5 m/s, walking
  SsmConfig a;
  SeparationTerms t = protectiveSeparation(a, 1.6, 0.5, 0.5, 0.5);
  EXPECT_NEAR(t.sh, 0.3376, 1e-15);  // 1.6 * (0.011 + 0.2)
  EXPECT_NEAR(t.sr, 0.0055, 1e-15);  // v_b = 0.5; 0.5 * 0.011
  EXPECT_NEAR(t.ss, 0.025, 1e-15);   // 0.5 * 0.5 * 0.2 / 2
  EXPECT_NEAR(t.total(), 0.4281, 1e-14);  // + Z_d 0.05 + Z_r 0.01
  // (b) the slow drive (T_r = 0.1, T_s = 0.5, C = 0.2, Z_d = 0.1, Z_r = 0.02), R = 0.8, on a resume
  // ramp: s = 0.25 now, s_b = 0.45 when braking would start; v_r = 0.2 m/s, a hand
  SsmConfig b;
  b.reactionTime = 0.1;
  b.stoppingTime = 0.5;
  b.intrusion = 0.2;
  b.personUncertainty = 0.1;
  b.robotUncertainty = 0.02;
  b.robotSpeed = 0.8;
  t = protectiveSeparation(b, 2.0, 0.2, 0.25, 0.45);
  EXPECT_NEAR(t.sh, 1.2, 1e-15);     // 2.0 * 0.6
  EXPECT_NEAR(t.sr, 0.036, 1e-15);   // v_b = 0.2 + 0.2 * 0.8 = 0.36; 0.36 * 0.1
  EXPECT_NEAR(t.ss, 0.0405, 1e-15);  // 0.36 * 0.45 * 0.5 / 2
  EXPECT_NEAR(t.total(), 1.5965, 1e-14);
  // (c) the light-curtain case at full program speed: (3) and (4) as written
  SsmConfig c;
  c.reactionTime = 0.05;
  c.stoppingTime = 0.3;
  c.intrusion = 0.85;
  c.personUncertainty = 0.0;
  c.robotUncertainty = 0.0;
  c.robotSpeed = 2.0;
  t = protectiveSeparation(c, 1.6, 2.0, 1.0, 1.0);
  EXPECT_NEAR(t.sr, 0.1, 1e-15);   // 2.0 * 0.05
  EXPECT_NEAR(t.ss, 0.3, 1e-15);   // 2.0 * 1 * 0.3 / 2
  EXPECT_NEAR(t.total(), 1.81, 1e-14);
  // (d) the defaults (R = 1) scaled to s = s_b = 0.5 at a turn of the path: v_r = 0.05 m/s seen, but
  // the path may speed up to R while the arm stops, so v_b = s_b R = 0.5, as in (a)
  t = protectiveSeparation(a, 1.6, 0.05, 0.5, 0.5);
  EXPECT_NEAR(t.sr, 0.0055, 1e-15);  // 0.5 * 0.011
  EXPECT_NEAR(t.ss, 0.025, 1e-15);   // 0.5 * 0.5 * 0.2 / 2
  // the allowed speed: R f (T_r + T_c) + R f^2 T_s / 2 = room, room = d - v_h T_r - S_p(v_h, 0) (the
  // person comes on for T_r before the factor takes effect), solved on paper.
  // (a) d = 0.45: room = 0.45 - 1.6 * 0.011 - (0.3376 + 0.06) = 0.0348; 0.1 f^2 + 0.012 f - 0.0348 = 0,
  // f = (-0.012 + sqrt(0.000144 + 0.01392)) / 0.2 = (-0.012 + 0.118591736642989) / 0.2 = 0.532958683214944
  EXPECT_NEAR(allowedDrivenSpeed(a, 1.6, 0.45), 0.532958683214944, 1e-9);
  // (against formula (4) at T_s, the drive unknown: (0.45 - 1.6 * 0.001 - 0.3976) / 0.112 = 0.453571428571429 m/s)
  EXPECT_NEAR(allowedRobotSpeed(a, 1.6, 0.45), 0.453571428571429, 1e-9);
  // (b) d = 2.0, a hand: room = 2.0 - 2.0 * 0.1 - (1.2 + 0.32) = 0.28, r = room / R = 0.35;
  // 0.25 f^2 + 0.101 f - 0.35 = 0, f = (-0.101 + sqrt(0.010201 + 0.35)) / 0.5 = 0.998334953252633,
  // speed f R = 0.798667962602106
  EXPECT_NEAR(allowedDrivenSpeed(b, 2.0, 2.0), 0.798667962602106, 1e-9);
  // (c) d = 1.6: room = 1.6 - 1.6 * 0.05 - (0.56 + 0.85) = 0.11, r = 0.055;
  // 0.15 f^2 + 0.051 f - 0.055 = 0, f = (-0.051 + sqrt(0.002601 + 0.033)) / 0.3 = 0.458940908724076,
  // speed f R = 0.917881817448152
  EXPECT_NEAR(allowedDrivenSpeed(c, 1.6, 1.6), 0.917881817448152, 1e-9);
  // within S_h + Z of a hand: no speed
  EXPECT_LT(allowedDrivenSpeed(a, 2.0, 0.4), 0.0);
}

TEST(Ssm, DriveTellsTheSpeedAStopBrakesFrom) {
  // times in binary fractions (cycle 2^-10 s), so every ramp lands exactly
  BrakeConfig cfg;
  cfg.stoppingTime = 0.25;
  cfg.delay = 0.0078125;
  cfg.resumeAfter = 0.0625;
  constexpr double dt = 0.0009765625;
  ArmDrive d(cfg);
  for (long k = 0; k <= 400; ++k) {
    const double t = static_cast<double>(k) * dt;
    d.advance(t);
    if (k == 32) {
      EXPECT_EQ(d.brakingSpeed(), 1.0);  // following
    }
    // braking: s now. STOP at 0.0625, braking from 0.0703125 at 4 per second: at 0.1953125, 1 - 0.125 * 4
    if (k == 200) {
      EXPECT_EQ(d.brakingSpeed(), 0.5);
    }
    d.observe(t, k == 64, k == 64, 1.0);
  }
  // at rest at 0.3203125, no threat for 0.0625 s by then: resumes at 4 per second; at 0.390625 the
  // speed is 0.0703125 * 4 = 0.28125, and a STOP would brake from the ramp's speed at 0.3984375: 0.3125
  EXPECT_EQ(d.mode(), DriveMode::Resuming);
  EXPECT_DOUBLE_EQ(d.speed(), 0.28125);
  EXPECT_DOUBLE_EQ(d.brakingSpeed(), 0.3125);
  // scaled: the speed now (held until braking starts)
  ArmDrive e(cfg);
  for (long k = 0; k <= 300; ++k) {
    const double t = static_cast<double>(k) * dt;
    e.advance(t);
    if (k == 0) e.limit(t, 0.4);
  }
  EXPECT_EQ(e.mode(), DriveMode::Scaled);
  EXPECT_DOUBLE_EQ(e.speed(), 0.4);  // 1 -> 0.4 from 0.0078125 at 4 per second: there by 0.1578
  EXPECT_DOUBLE_EQ(e.brakingSpeed(), 0.4);
}

TEST(Pfl, SpeedLimitsEqualAnnexAByHand) {
  // ISO/TS 15066 Annex A per region (Table A.2 quasi-static force F, x 2 for transient contact;
  // Table A.3 K, m_H): v = 2F / sqrt(mu K), mu = m_H m_R / (m_H + m_R), m_R = M / 2 + m_L.
  // Each value below was worked out on paper from those numbers, not with the code under test.
  // (a) the default Panda: M = 18 kg, m_L = 1 kg -> m_R = 9 + 1 = 10 kg
  SsmConfig a;
  EXPECT_NEAR(robotEffectiveMass(a.armMass, a.payload), 10.0, 1e-12);
  // hand: mu = 0.6 * 10 / 10.6 = 0.566037735849057; mu K = 0.566037735849057 * 75000 = 42452.8301886792;
  // v = 280 / sqrt(42452.8301886792) = 280 / 206.040845 = 1.35895384599903 m/s
  EXPECT_NEAR(reducedMass(0.6, 10.0), 0.566037735849057, 1e-12);
  EXPECT_NEAR(pflSpeedLimit(a, BodyRegion::Hand), 1.35895384599903, 1e-9);
  // chest (the torso): mu = 40 * 10 / 50 = 8; mu K = 8 * 25000 = 200000; v = 280 / 447.213595 = 0.626099033699941
  EXPECT_NEAR(pflSpeedLimit(a, BodyRegion::Chest), 0.626099033699941, 1e-9);
  // pelvis: mu 8; v = 360 / sqrt(8 * 25000) = 360 / 447.213595 = 0.804984471899924
  EXPECT_NEAR(pflSpeedLimit(a, BodyRegion::Pelvis), 0.804984471899924, 1e-9);
  // upper arm: mu = 3 * 10 / 13 = 2.30769230769231; mu K = 69230.7692307692; v = 300 / 263.117 = 1.14017542509914
  EXPECT_NEAR(pflSpeedLimit(a, BodyRegion::UpperArm), 1.14017542509914, 1e-9);
  // lower arm: mu = 2 * 10 / 12 = 1.66666666666667; mu K = 66666.6666666667; v = 320 / 258.199 = 1.23935467078637
  EXPECT_NEAR(pflSpeedLimit(a, BodyRegion::LowerArm), 1.23935467078637, 1e-9);
  // thigh: mu = 75 * 10 / 85 = 8.82352941176471; mu K = 441176.470588235; v = 440 / 664.211 = 0.662439934383991
  EXPECT_NEAR(pflSpeedLimit(a, BodyRegion::Thigh), 0.662439934383991, 1e-9);
  // lower leg: mu 8.82352941176471; mu K = 529411.764705882; v = 260 / 727.607 = 0.357335820886864
  EXPECT_NEAR(pflSpeedLimit(a, BodyRegion::LowerLeg), 0.357335820886864, 1e-9);
  // skull: mu = 4.4 * 10 / 14.4 = 3.05555555555556; mu K = 458333.333333333; v = 260 / 677.003 = 0.384045451855518,
  // but the head takes no transient contact under pfl: its limit is 0 (and so the neck's)
  EXPECT_NEAR(transientSpeedLimit(260.0, 150e3, reducedMass(4.4, 10.0)), 0.384045451855518, 1e-9);
  EXPECT_EQ(pflSpeedLimit(a, BodyRegion::Skull), 0.0);
  EXPECT_EQ(pflSpeedLimit(a, BodyRegion::Neck), 0.0);
  // neck's numbers all the same: mu = 1.2 * 10 / 11.2 = 1.07142857142857; v = 300 / sqrt(53571.4285714286) = 1.29614813968157
  EXPECT_NEAR(transientSpeedLimit(300.0, 50e3, reducedMass(1.2, 10.0)), 1.29614813968157, 1e-9);

  // (b) a heavier arm with a load: M = 30 kg, m_L = 5 kg -> m_R = 15 + 5 = 20 kg
  SsmConfig b;
  b.armMass = 30.0;
  b.payload = 5.0;
  EXPECT_NEAR(robotEffectiveMass(b.armMass, b.payload), 20.0, 1e-12);
  // hand: mu = 0.6 * 20 / 20.6 = 0.58252427184466; mu K = 43689.3203883495; v = 280 / 209.019 = 1.33958534214468
  EXPECT_NEAR(pflSpeedLimit(b, BodyRegion::Hand), 1.33958534214468, 1e-9);
  // chest: mu = 40 * 20 / 60 = 13.3333333333333; mu K = 333333.333333333; v = 280 / 577.350 = 0.484974226119286
  EXPECT_NEAR(pflSpeedLimit(b, BodyRegion::Chest), 0.484974226119286, 1e-9);
  // pelvis: v = 360 / 577.350 = 0.623538290724796
  EXPECT_NEAR(pflSpeedLimit(b, BodyRegion::Pelvis), 0.623538290724796, 1e-9);
  // upper arm: mu = 3 * 20 / 23 = 2.60869565217391; mu K = 78260.8695652174; v = 300 / 279.751 = 1.07238052947636
  EXPECT_NEAR(pflSpeedLimit(b, BodyRegion::UpperArm), 1.07238052947636, 1e-9);
  // lower arm: mu = 2 * 20 / 22 = 1.81818181818182; mu K = 72727.2727272727; v = 320 / 269.680 = 1.18659175793531
  EXPECT_NEAR(pflSpeedLimit(b, BodyRegion::LowerArm), 1.18659175793531, 1e-9);
  // thigh: mu = 75 * 20 / 95 = 15.7894736842105; mu K = 789473.684210526; v = 440 / 888.523 = 0.495203661806601
  EXPECT_NEAR(pflSpeedLimit(b, BodyRegion::Thigh), 0.495203661806601, 1e-9);
  // lower leg: mu 15.7894736842105; mu K = 947368.421052632; v = 260 / 973.328 = 0.267124606795322
  EXPECT_NEAR(pflSpeedLimit(b, BodyRegion::LowerLeg), 0.267124606795322, 1e-9);
  // skull: mu = 4.4 * 20 / 24.4 = 3.60655737704918; v = 260 / sqrt(540983.606557377) = 0.353493388562751
  EXPECT_NEAR(transientSpeedLimit(260.0, 150e3, reducedMass(4.4, 20.0)), 0.353493388562751, 1e-9);

  // (c) a light arm, nothing carried: M = 4 kg, m_L = 0 -> m_R = 2 kg
  SsmConfig c;
  c.armMass = 4.0;
  c.payload = 0.0;
  EXPECT_NEAR(robotEffectiveMass(c.armMass, c.payload), 2.0, 1e-12);
  // hand: mu = 0.6 * 2 / 2.6 = 0.461538461538462; mu K = 34615.3846153846; v = 280 / 186.052 = 1.5049547796824
  EXPECT_NEAR(pflSpeedLimit(c, BodyRegion::Hand), 1.5049547796824, 1e-9);
  // chest: mu = 40 * 2 / 42 = 1.9047619047619; mu K = 47619.0476190476; v = 280 / 218.218 = 1.28312119458764
  EXPECT_NEAR(pflSpeedLimit(c, BodyRegion::Chest), 1.28312119458764, 1e-9);
  // pelvis: v = 360 / 218.218 = 1.6497272501841
  EXPECT_NEAR(pflSpeedLimit(c, BodyRegion::Pelvis), 1.6497272501841, 1e-9);
  // upper arm: mu = 3 * 2 / 5 = 1.2; mu K = 36000; v = 300 / 189.737 = 1.58113883008419
  EXPECT_NEAR(pflSpeedLimit(c, BodyRegion::UpperArm), 1.58113883008419, 1e-9);
  // lower arm: mu = 2 * 2 / 4 = 1; mu K = 40000; v = 320 / 200 = 1.6 exactly
  EXPECT_NEAR(pflSpeedLimit(c, BodyRegion::LowerArm), 1.6, 1e-9);
  // thigh: mu = 75 * 2 / 77 = 1.94805194805195; mu K = 97402.5974025974; v = 440 / 312.094 = 1.40983214130856
  EXPECT_NEAR(pflSpeedLimit(c, BodyRegion::Thigh), 1.40983214130856, 1e-9);
  // lower leg: mu K = 116883.116883117; v = 260 / 341.882 = 0.760496913573984
  EXPECT_NEAR(pflSpeedLimit(c, BodyRegion::LowerLeg), 0.760496913573984, 1e-9);
  // skull: mu = 4.4 * 2 / 6.4 = 1.375; mu K = 206250; v = 260 / 454.148 = 0.572501157865708
  EXPECT_NEAR(transientSpeedLimit(260.0, 150e3, reducedMass(4.4, 2.0)), 0.572501157865708, 1e-9);
  // the energy balance (A.5) = (A.6) at the limit: F^2 / (2 K) = mu v^2 / 2, e.g. (c)'s lower arm:
  // 320^2 / 80000 = 1.28 J = 1 * 1.6^2 / 2
  EXPECT_NEAR(0.5 * reducedMass(2.0, 2.0) * std::pow(pflSpeedLimit(c, BodyRegion::LowerArm), 2), 1.28, 1e-9);
}

TEST(Pfl, ClampedAndMovingLimitsEqualAnnexAByHand) {
  // Clamped (quasi-static): v = F / sqrt(m_R K), F Table A.2's quasi-static force (half the
  // transient) and the region backed by the obstacle (mu -> m_R). A region moving into the arm at
  // v_p: the robot's limit is v_rel,max - v_p, never below 0. Worked out on paper:
  // (a) M = 18 kg, m_L = 1 kg: m_R = 10 kg
  SsmConfig a;
  // chest clamped: 140 / sqrt(10 * 25000) = 140 / 500 = 0.28
  EXPECT_NEAR(pflSpeedLimit(a, BodyRegion::Chest, true, 0.0), 0.28, 1e-12);
  // hand clamped: 140 / sqrt(10 * 75000) = 140 / 866.025404 = 0.161658075373095
  EXPECT_NEAR(pflSpeedLimit(a, BodyRegion::Hand, true, 0.0), 0.161658075373095, 1e-9);
  // chest transient, the person moving into the arm at 0.2 m/s: 0.626099033699941 - 0.2
  EXPECT_NEAR(pflSpeedLimit(a, BodyRegion::Chest, false, 0.2), 0.426099033699941, 1e-9);
  // a hand coming at 2.0 m/s is beyond its transient limit (1.359 m/s) on its own: 0
  EXPECT_EQ(pflSpeedLimit(a, BodyRegion::Hand, false, 2.0), 0.0);
  // the head takes no contact, clamped or not
  EXPECT_EQ(pflSpeedLimit(a, BodyRegion::Skull, true, 0.0), 0.0);
  // (b) M = 30 kg, m_L = 5 kg: m_R = 20 kg
  SsmConfig b;
  b.armMass = 30.0;
  b.payload = 5.0;
  // thigh clamped: 220 / sqrt(20 * 50000) = 220 / 1000 = 0.22
  EXPECT_NEAR(pflSpeedLimit(b, BodyRegion::Thigh, true, 0.0), 0.22, 1e-12);
  // lower leg clamped: 130 / sqrt(20 * 60000) = 130 / 1095.445115 = 0.118673220792786
  EXPECT_NEAR(pflSpeedLimit(b, BodyRegion::LowerLeg, true, 0.0), 0.118673220792786, 1e-9);
  // thigh transient moving in at 0.3 m/s: 0.495203661806601 - 0.3
  EXPECT_NEAR(pflSpeedLimit(b, BodyRegion::Thigh, false, 0.3), 0.195203661806601, 1e-9);
  // (c) M = 4 kg, m_L = 0: m_R = 2 kg
  SsmConfig c;
  c.armMass = 4.0;
  c.payload = 0.0;
  // lower arm clamped: 160 / sqrt(2 * 40000) = 160 / 282.842712 = 0.565685424949238
  EXPECT_NEAR(pflSpeedLimit(c, BodyRegion::LowerArm, true, 0.0), 0.565685424949238, 1e-9);
  // hand clamped, moving in at 0.1 m/s: 140 / sqrt(2 * 75000) - 0.1 = 0.361478445646026 - 0.1
  EXPECT_NEAR(pflSpeedLimit(c, BodyRegion::Hand, true, 0.1), 0.261478445646026, 1e-9);
  // upper arm transient moving in at 1.0 m/s: 300 / sqrt(1.2 * 30000) - 1 = 1.58113883008419 - 1
  EXPECT_NEAR(pflSpeedLimit(c, BodyRegion::UpperArm, false, 1.0), 0.58113883008419, 1e-9);
  // clamped is never above half the transient limit (the same region, at rest): F vs 2F, m_R >= mu
  for (const SsmConfig* cfg : {&a, &b, &c})
    for (int r = 0; r <= static_cast<int>(BodyRegion::LowerLeg); ++r)
      EXPECT_LE(pflSpeedLimit(*cfg, BodyRegion(r), true, 0.0), 0.5 * pflSpeedLimit(*cfg, BodyRegion(r), false, 0.0) + 1e-15);
  // the gap within which a fixed obstacle pins a region: R (T_r + T_s / 2) + C + Z_d + Z_r
  // = 1.0 (0.011 + 0.1) + 0 + 0.05 + 0.01 = 0.171 m for the defaults
  EXPECT_NEAR(clampGap(a), 0.171, 1e-12);
}

TEST(Pfl, PartSpeedIntoTheArmIsItsApproachComponent) {
  // a hand (right wrist -> right hand) 0.5 m from an arm capsule along +x; its joints' velocities
  SsmConfig cfg;
  const int hand = 7;  // bodyParts()[7]: the right hand
  ASSERT_EQ(bodyParts()[hand].region, BodyRegion::Hand);
  ASSERT_EQ(bodyParts()[hand].a, kRightWrist);
  ASSERT_EQ(bodyParts()[hand].b, kRightHand);
  const Capsule body{Vec3(0, 0, 1), Vec3(0, 0.1, 1), 0.04};
  const Capsule arm{Vec3(0.5, -1, 1), Vec3(0.5, 1, 1), 0.05};
  std::array<Vec3, kSkeletonJoints> v;
  v.fill(Vec3::Zero());
  // moving straight at the arm at 1.2 m/s: all of it
  v[kRightWrist] = v[kRightHand] = Vec3(1.2, 0, 0);
  EXPECT_NEAR(partSpeedInto(cfg, hand, body, arm, true, v), 1.2, 1e-12);
  // along the arm (past it) and away: nothing into it
  v[kRightWrist] = v[kRightHand] = Vec3(0, 1.5, 0);
  EXPECT_NEAR(partSpeedInto(cfg, hand, body, arm, true, v), 0.0, 1e-12);
  v[kRightWrist] = v[kRightHand] = Vec3(-1.0, 0, 0);
  EXPECT_EQ(partSpeedInto(cfg, hand, body, arm, true, v), 0.0);
  // at 45 degrees, 2 m/s, only the hand joint: 2 cos 45 = 1.41421356237310
  v[kRightWrist] = Vec3::Zero();
  v[kRightHand] = Vec3(std::sqrt(2.0), std::sqrt(2.0), 0);
  EXPECT_NEAR(partSpeedInto(cfg, hand, body, arm, true, v), 1.4142135623731, 1e-12);
  // velocities unknown: the standard's hand speed
  EXPECT_EQ(partSpeedInto(cfg, hand, body, arm, false, v), cfg.handSpeed);
  // touching: the larger joint speed, whatever its direction (2 m/s)
  const Capsule touching{Vec3(0.05, -1, 1), Vec3(0.05, 1, 1), 0.05};
  EXPECT_NEAR(partSpeedInto(cfg, hand, body, touching, true, v), 2.0, 1e-12);
}

TEST(Pfl, AFixedObstacleNearARegionBelowSpClampsIt) {
  // a post (as PostWalk's) and a person standing 0.45 m from it (every part below S_p, at rest),
  // a sphere beside the right hand: within clampGap of it the verdict is clamped, beyond it not,
  // and a tracked (movable) sphere never clamps
  ArmModel m;
  m.name = "post";
  m.joints = {{0, 0, 0.1, 0, -1, 1}};
  m.capsules = {{0, {0, 0, 0}, {0, 0, 1.5}, 0.1}};
  m.resetAllowedToAdjacent();
  PersonScript script;
  script.start = Vec3(0.45, 0, 0);
  script.heading = M_PI;
  PersonSet persons;
  persons.add("stander", std::make_unique<ScriptedPerson>(script));
  persons.pose(0.5);
  ASSERT_TRUE(persons.velocitiesKnown(0));
  const Capsule handCap = bodyCapsules(persons.skeleton(0))[7];
  SsmConfig cfg;
  cfg.response = SsmResponse::Pfl;
  const double gap = clampGap(cfg);
  auto clampedWith = [&](double clearance, bool tracked) {
    Obstacle o;
    o.name = "table";
    o.kind = ShapeKind::Sphere;
    o.sphere.radius = 0.05;
    // beside the hand's lower end, on its outer side (away from the body), `clearance` from the
    // hand's surface: no other region is as near
    const Vec3 low = handCap.a.z() < handCap.b.z() ? handCap.a : handCap.b;
    const double side = low.y() >= 0.0 ? 1.0 : -1.0;
    o.sphere.center = low + Vec3(0, side * (handCap.radius + clearance + o.sphere.radius), 0);
    o.tracked = tracked;
    Monitor mon({ArmInstance{"post", m, Eigen::Isometry3d::Identity()}}, {o}, SafetyConfig{});
    const double q = 0.0, qd = 0.0;
    mon.setJointState(0, 0.5, &q, &qd);
    mon.cycle(0.5);
    SeparationMonitor ssm(cfg, 1);
    ssm.cycle(mon, persons);
    EXPECT_LT(ssm.verdict(0).slack, 0.0);
    return ssm.verdict(0).clamped;
  };
  EXPECT_TRUE(clampedWith(0.5 * gap, false));
  EXPECT_TRUE(clampedWith(gap - 1e-6, false));
  EXPECT_FALSE(clampedWith(gap + 1e-3, false));
  EXPECT_FALSE(clampedWith(0.5 * gap, true));
}

TEST(Person, ReachableCapsuleHoldsEverySampledMotion) {
  // end points moving at most v (any direction, changing every 10 ms): every point of the moved
  // capsule stays inside the capsule grown by v t
  std::mt19937_64 rng(7);
  std::uniform_real_distribution<double> u(-1.0, 1.0), u01(0.0, 1.0);
  auto unit = [&] {
    Vec3 d(u(rng), u(rng), u(rng));
    while (d.norm() < 1e-3) d = Vec3(u(rng), u(rng), u(rng));
    return Vec3(d.normalized());
  };
  for (int trial = 0; trial < 2000; ++trial) {
    const Capsule c0{Vec3(u(rng), u(rng), u(rng)), Vec3(u(rng), u(rng), u(rng)), 0.02 + 0.1 * u01(rng)};
    const double v = trial % 2 ? 2.0 : 1.6, T = 0.211;
    Vec3 a = c0.a, b = c0.b;
    for (double t = 0.0; t < T;) {
      const double dt = std::min(0.01, T - t);
      a += unit() * (v * u01(rng) * dt);
      b += unit() * (v * u01(rng) * dt);
      t += dt;
      const Capsule grown = reachable(c0, v, t);
      for (int k = 0; k < 20; ++k) {
        const double s = u01(rng);
        const Vec3 p = a + s * (b - a) + unit() * c0.radius;  // on the moved capsule's surface
        // distance from p to the original axis
        const Vec3 ab = c0.b - c0.a;
        const double w = std::clamp((p - c0.a).dot(ab) / ab.squaredNorm(), 0.0, 1.0);
        ASSERT_LE((p - (c0.a + w * ab)).norm(), grown.radius + 1e-12) << trial;
      }
    }
  }
}

// A post (one capsule, 0..1.5 m high, radius 0.1) at the origin and a person walking at 1 m/s
// along x towards it from x = 3. Each body part's distance to the post is worked out from the
// standing pose (all parts beside the post's height): head x - 0.21, torso x - 0.27, upper arm
// sqrt(x^2 + 0.2^2) - 0.15, lower arm sqrt(x^2 + 0.22^2) - 0.14, hand sqrt(x^2 + 0.22^2) - 0.15,
// thigh sqrt(x^2 + 0.1^2) - 0.18, lower leg sqrt(x^2 + 0.1^2) - 0.16.
struct PostWalk {
  static constexpr double x0 = 3.0, speed = 1.0, dt = 0.001;
  // the largest x at which some part's distance is below its own threshold R(vh)
  static double crossing(const std::function<double(double vh)>& R) {
    const double body = R(1.6), hand = R(2.0);
    auto radial = [](double r, double y, double c) { return std::sqrt((r + c) * (r + c) - y * y); };
    return std::max({body + 0.21, body + 0.27, radial(body, 0.2, 0.15), radial(body, 0.22, 0.14), radial(hand, 0.22, 0.15),
                     radial(body, 0.1, 0.18), radial(body, 0.1, 0.16)});
  }
  // first cycle time at which pred(verdict) holds
  static double first(SsmResponse response, const std::function<bool(const SsmVerdict&)>& pred, SsmConfig cfg) {
    ArmModel m;
    m.name = "post";
    m.joints = {{0, 0, 0.1, 0, -1, 1}};
    m.capsules = {{0, {0, 0, 0}, {0, 0, 1.5}, 0.1}};
    m.resetAllowedToAdjacent();
    Monitor mon({ArmInstance{"post", m, Eigen::Isometry3d::Identity()}}, {}, SafetyConfig{});
    PersonScript script;
    script.start = Vec3(x0, 0, 0);
    script.heading = M_PI;
    script.actions = {{PersonAction::Walk, Vec3(0.0, 0, 0), speed, 0.0, true}};
    PersonSet persons;
    persons.add("walker", std::make_unique<ScriptedPerson>(script));
    cfg.response = response;
    SeparationMonitor ssm(cfg, 1);
    const double q = 0.0, qd = 0.0;
    for (long k = 0; k < 3000; ++k) {
      const double t = static_cast<double>(k) * dt;
      mon.setJointState(0, t, &q, &qd);
      mon.cycle(t);
      persons.pose(t);
      ssm.cycle(mon, persons);
      if (pred(ssm.verdict(0))) return t;
    }
    return NAN;
  }
};

TEST(Ssm, WalkingPersonTransitionsAtTheSolvedTimes) {
  SsmConfig cfg;
  cfg.robotSpeed = 1.1;
  const double P = cfg.reactionTime + cfg.stoppingTime / 2.0 + cfg.cycleTime;
  auto S0 = [&](double vh) { return vh * (cfg.reactionTime + cfg.stoppingTime) + cfg.personUncertainty + cfg.robotUncertainty; };
  auto expectAt = [&](double xStar, double t, const char* what) {
    const double tStar = (PostWalk::x0 - xStar) / PostWalk::speed;
    // the first cycle past the crossing (d < threshold from there on)
    EXPECT_GT(t, tStar - 1e-9) << what;
    EXPECT_LE(t, tStar + PostWalk::dt + 1e-9) << what << " solved " << tStar;
  };
  // binary: STOP below S_p at the arm's top speed (the post stands still, v_r = 0)
  expectAt(PostWalk::crossing([&](double vh) { return S0(vh) + 1.1 * (cfg.reactionTime + cfg.stoppingTime / 2.0); }),
           PostWalk::first(SsmResponse::Stop, [](const SsmVerdict& v) { return v.stop; }, cfg), "binary STOP");
  // scaling: slowing where the top speed no longer keeps S_p at the next cycle, at rest where no
  // speed does, STOP only below S_p at rest
  expectAt(PostWalk::crossing([&](double vh) { return S0(vh) + vh * cfg.cycleTime + 1.1 * P; }),
           PostWalk::first(SsmResponse::Scaling, [](const SsmVerdict& v) { return v.factor < 1.0; }, cfg), "scaling");
  expectAt(PostWalk::crossing([&](double vh) { return S0(vh) + vh * cfg.cycleTime; }),
           PostWalk::first(SsmResponse::Scaling, [](const SsmVerdict& v) { return v.factor == 0.0; }, cfg), "factor 0");
  expectAt(PostWalk::crossing(S0), PostWalk::first(SsmResponse::Scaling, [](const SsmVerdict& v) { return v.stop; }, cfg),
           "scaling STOP");
}

TEST(Pfl, WalkingPersonSlowsTheArmByRegionAndNeverStopsAResting) {
  SsmConfig cfg;
  cfg.robotSpeed = 1.1;
  const double S0 = 1.6 * (cfg.reactionTime + cfg.stoppingTime) + cfg.personUncertainty + cfg.robotUncertainty;
  auto expectAt = [&](double xStar, double t, const char* what) {
    const double tStar = (PostWalk::x0 - xStar) / PostWalk::speed;
    EXPECT_GT(t, tStar - 1e-9) << what;
    EXPECT_LE(t, tStar + PostWalk::dt + 1e-9) << what << " solved " << tStar;
  };
  // the person walks into the post at 1 m/s: each region's limit is its transient one less its
  // speed into the post: the torso (chest) 0.626 - 1 -> 0, the legs 0.662 / 0.357 - ~1 -> 0, the
  // hand about 1.359 - 0.98, the arms about 1.140 / 1.239 - 0.98. The torso slows the arm where
  // S_p's own speed falls below 1.1 m/s at the torso: x - 0.27 = S0 + 1.6 T_c + 1.1 (T_r + T_s / 2
  // + T_c) = 0.792 m (the hand's and arms' S_p crossings for 1.1 m/s come later: 0.72 and 0.64 m)
  const double P = cfg.reactionTime + cfg.stoppingTime / 2.0 + cfg.cycleTime;
  expectAt(0.27 + S0 + 1.6 * cfg.cycleTime + 1.1 * P,
           PostWalk::first(SsmResponse::Pfl, [](const SsmVerdict& v) { return v.factor < 1.0; }, cfg), "pfl slows");
  // factor 0 where a region of limit 0 leaves no speed: the torso (walking into the post faster
  // than its limit) before the head: x - 0.27 = S0 + 1.6 T_c
  expectAt(0.27 + S0 + 1.6 * cfg.cycleTime,
           PostWalk::first(SsmResponse::Pfl, [](const SsmVerdict& v) { return v.factor == 0.0; }, cfg), "pfl factor 0");
  // below S_p at rest first with the torso (x - 0.27 = S0): allowed by PFL, the post does not move
  expectAt(0.27 + S0, PostWalk::first(SsmResponse::Pfl, [](const SsmVerdict& v) { return v.pflAllowed; }, cfg),
           "pfl below S_p allowed");
  // a post at rest is never stopped under pfl (0 m/s is within every limit, the head's 0 too)
  EXPECT_TRUE(std::isnan(PostWalk::first(SsmResponse::Pfl, [](const SsmVerdict& v) { return v.stop; }, cfg)));
}

// minimum over sampled point pairs of two capsules' axes, minus the radii
double sampledDistance(const Capsule& a, const Capsule& b, int n) {
  double best = INFINITY;
  for (int i = 0; i < n; ++i) {
    const Vec3 p = a.a + (static_cast<double>(i) / (n - 1)) * (a.b - a.a);
    for (int j = 0; j < n; ++j) {
      const Vec3 q = b.a + (static_cast<double>(j) / (n - 1)) * (b.b - b.a);
      best = std::min(best, (p - q).norm());
    }
  }
  return std::max(0.0, best - a.radius - b.radius);
}

TEST(Ssm, SeparationEqualsBruteForceSampling) {
  // a Panda at random poses, a person at random places reaching at random points
  std::mt19937_64 rng(11);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Monitor mon({ArmInstance{"panda", pandaModel(), Eigen::Isometry3d::Identity()}}, {}, SafetyConfig{});
  const ArmModel& pm = mon.arm(0).model;
  constexpr int n = 301;
  for (int trial = 0; trial < 12; ++trial) {
    std::vector<double> q(7), qd(7, 0.0);
    for (int k = 0; k < 7; ++k) q[k] = 0.5 * (pm.joints[k].lower + pm.joints[k].upper) + 0.4 * u(rng);
    mon.setJointState(0, trial, q.data(), qd.data());
    mon.cycle(trial);
    PersonScript s;
    s.start = Vec3(0.9 + 0.4 * u(rng), 0.6 * u(rng), 0);
    s.heading = M_PI + 0.5 * u(rng);
    s.actions = {{PersonAction::Reach, Vec3(0.4 + 0.2 * u(rng), 0.3 * u(rng), 0.6 + 0.3 * u(rng)), 2.0, 0.0, trial % 2 == 0}};
    PersonSet persons;
    persons.add("p", std::make_unique<ScriptedPerson>(s));
    persons.pose(10.0);  // reach done
    SeparationMonitor ssm(SsmConfig{}, 1);
    ssm.cycle(mon, persons);
    double brute = INFINITY, bound = 0.0;
    const auto body = bodyCapsules(persons.skeleton(0));
    for (int i = 0; i < mon.capsuleCount(); ++i)
      for (const Capsule& pc : body) {
        const Capsule ac = mon.movingCapsule(i).c;
        const double d = sampledDistance(ac, pc, n);
        // the true closest pair lies within half a sample step of a sampled one on each axis
        const double err = 0.5 * ((ac.b - ac.a).norm() + (pc.b - pc.a).norm()) / (n - 1);
        if (d < brute) brute = d, bound = err;
      }
    EXPECT_LE(ssm.verdict(0).separation, brute + 1e-12) << trial;
    EXPECT_GE(ssm.verdict(0).separation, brute - bound - 1e-12) << trial;
  }
}

TEST(Ssm, VerdictEqualsEveryPairOneByOne) {
  // the monitor measures each body part against its nearest arm capsule only (spheres around the
  // capsules skip the pairs that cannot be nearer); the verdict must be the one every pair taken
  // one by one gives, (1)-(4) and (A.7) applied pair by pair as written (the drive unknown: formulae
  // (3) and (4) at full program speed), for two persons near a moving Panda at random poses
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  Monitor mon({ArmInstance{"panda", pandaModel(), Eigen::Isometry3d::Identity()}}, {}, SafetyConfig{});
  const ArmModel& pm = mon.arm(0).model;
  int stops = 0, scaled = 0;
  for (int trial = 0; trial < 40; ++trial) {
    std::vector<double> q(7), qd(7);
    for (int k = 0; k < 7; ++k) {
      q[k] = 0.5 * (pm.joints[k].lower + pm.joints[k].upper) + 0.4 * u(rng);
      qd[k] = 0.8 * u(rng);
    }
    mon.setJointState(0, trial, q.data(), qd.data());
    mon.cycle(trial);
    PersonSet persons;
    for (int p = 0; p < 2; ++p) {
      PersonScript s;
      s.start = Vec3(0.8 + 0.8 * std::abs(u(rng)), 0.8 * u(rng), 0);
      s.heading = M_PI + 0.5 * u(rng);
      s.actions = {{PersonAction::Reach, Vec3(0.4 + 0.3 * u(rng), 0.4 * u(rng), 0.5 + 0.4 * u(rng)), 2.0, 0.0, trial % 2 == 0}};
      persons.add(p == 0 ? "first" : "second", std::make_unique<ScriptedPerson>(s));
    }
    persons.pose(10.0);
    for (SsmResponse r : {SsmResponse::Stop, SsmResponse::Scaling, SsmResponse::Pfl}) {
      SsmConfig cfg;
      cfg.response = r;
      SeparationMonitor ssm(cfg, 1);
      ssm.cycle(mon, persons);
      const SsmVerdict& v = ssm.verdict(0);
      // pair by pair
      double vr = 0.0;
      for (int i = 0; i < mon.capsuleCount(); ++i)
        vr = std::max({vr, mon.movingCapsule(i).va.norm(), mon.movingCapsule(i).vb.norm()});
      double sep = INFINITY, worst = INFINITY, allowed = INFINITY, pflAllowed = INFINITY, required = 0.0;
      int part = -1, person = -1, armBody = -1;
      bool binary = false, pflBreak = false;
      for (int i = 0; i < mon.capsuleCount(); ++i)
        for (int p = 0; p < 2; ++p) {
          const auto body = bodyCapsules(persons.skeleton(p));
          for (int k = 0; k < kBodyParts; ++k) {
            const double vh = bodyParts()[k].hand ? cfg.handSpeed : cfg.bodySpeed;
            const double d = distance(mon.movingCapsule(i).c, body[k]);
            const double sp = protectiveSeparation(cfg, vh, vr).total();
            if (d - sp < worst) worst = d - sp, required = sp, part = k, person = p, armBody = mon.capsuleBody(i);
            sep = std::min(sep, d);
            const double a = allowedRobotSpeed(cfg, vh, d);
            allowed = std::min(allowed, a);
            pflAllowed = std::min(pflAllowed, std::max(a, pflSpeedLimit(cfg, bodyParts()[k].region)));
            if (d - sp < 0.0 && vr > pflSpeedLimit(cfg, bodyParts()[k].region)) pflBreak = true;
            if (d < protectiveSeparation(cfg, vh, std::max(cfg.robotSpeed, vr)).total()) binary = true;
          }
        }
      std::ostringstream at;  // (not string +: GCC 12's -Wrestrict false positive)
      at << "trial " << trial << " " << toString(r);
      EXPECT_EQ(v.separation, sep) << at.str();
      EXPECT_EQ(v.slack, worst) << at.str();
      EXPECT_EQ(v.required, required) << at.str();
      EXPECT_EQ(v.person, person) << at.str();
      EXPECT_EQ(v.part, part) << at.str();
      EXPECT_EQ(v.armBody, armBody) << at.str();
      EXPECT_EQ(v.robotSpeed, vr) << at.str();
      if (r == SsmResponse::Stop) {
        EXPECT_EQ(v.stop, binary) << at.str();
      } else if (r == SsmResponse::Scaling) {
        EXPECT_EQ(v.allowedSpeed, allowed) << at.str();
        EXPECT_EQ(v.stop, worst < 0.0) << at.str();
        EXPECT_EQ(v.factor, v.stop ? 0.0 : std::clamp(allowed / cfg.robotSpeed, 0.0, 1.0)) << at.str();
        stops += v.stop;
        scaled += !v.stop && v.factor < 1.0;
      } else {
        EXPECT_EQ(v.allowedSpeed, pflAllowed) << at.str();
        EXPECT_EQ(v.stop, pflBreak) << at.str();
      }
    }
  }
  // the trials cover both verdicts that matter
  EXPECT_GT(stops, 0);
  EXPECT_GT(scaled, 0);
}

TEST(ArmDrive, ScalingFollowsTheFactorAtTheBrakingRate) {
  BrakeConfig cfg;
  cfg.stoppingTime = 0.2;
  cfg.delay = 0.01;
  ArmDrive d(cfg);
  double tau = 0.0;
  for (long k = 0; k <= 2000; ++k) {
    const double t = static_cast<double>(k) * 0.001;
    tau = d.advance(t);
    if (k == 1000) {
      // s = 1 until 0.51, down to 0.5 at 0.61: tau = 0.51 + 0.075 + 0.5 (1.0 - 0.61)
      EXPECT_NEAR(tau, 0.78, 1e-12);
      EXPECT_NEAR(d.speed(), 0.5, 1e-12);
      EXPECT_EQ(d.mode(), DriveMode::Scaled);
    }
    if (k == 500) d.limit(t, 0.5);
    if (k == 1000) d.limit(t, 1.0);
  }
  // back up from 1.01 to 1 at 1.11: tau = 0.78 + 0.005 + 0.075 + 0.89
  EXPECT_NEAR(tau, 1.75, 1e-12);
  EXPECT_EQ(d.mode(), DriveMode::Following);
  EXPECT_DOUBLE_EQ(d.speed(), 1.0);
  // a STOP while scaled brakes from the scaled speed
  ArmDrive e(cfg);
  for (long k = 0; k <= 1000; ++k) {
    const double t = static_cast<double>(k) * 0.001;
    e.advance(t);
    if (k == 100) e.limit(t, 0.5);
    if (k == 500) e.observe(t, true, true, 1.0);
  }
  EXPECT_EQ(e.mode(), DriveMode::Stopped);
  EXPECT_EQ(e.speed(), 0.0);
}

// The pfl speed limits of the default masses (m_R = 10 kg), worked out by hand in
// Pfl.SpeedLimitsEqualAnnexAByHand, per body part in bodyParts() order: head (none), torso (chest),
// upper arm, lower arm, hand, x2, thigh, lower leg x2.
constexpr double kPflLimitsByHand[kBodyParts] = {0.0, 0.626099033699941, 1.14017542509914, 1.23935467078637,
                                                 1.35895384599903, 1.14017542509914, 1.23935467078637, 1.35895384599903,
                                                 0.662439934383991, 0.357335820886864, 0.662439934383991, 0.357335820886864};

TEST(Ssm, ClosedLoopNoPersonTouchesAMovingArm) {
  // every shipped person scenario (walking up, walking past, reaching at 2.0 and 1.6 m/s), every response
  double summed[3] = {0, 0, 0};
  for (const char* name : {"person_walkup", "person_walkpast", "person_reach"}) {
    const Scenario s = loadScenario(scenarioPath(name));
    ASSERT_EQ(s.persons.size(), 1u);
    // the reference: without the person the arm keeps its program's pace (program time = clock
    // time), and no response to the person does better
    const CoexistenceOutcome alone = runWithoutPersons(s);
    EXPECT_EQ(alone.stops, 0) << name;
    EXPECT_EQ(alone.stopCycles + alone.scaledCycles, 0u) << name;
    EXPECT_NEAR(alone.progress, 1.0, 1e-9) << name;
    double progress[3] = {0, 0, 0};
    int k = 0;
    for (SsmResponse r : {SsmResponse::Stop, SsmResponse::Scaling, SsmResponse::Pfl}) {
      std::uint64_t unstopped = 0, cycles = 0, touched = 0, touchedFast = 0;
      double minSep = INFINITY;
      PersonSet persons = makePersons(s);
      const CoexistenceOutcome o = runCoexistence(s, r, [&](const Monitor& m, const SeparationMonitor& ssm) {
        ++cycles;
        const SsmVerdict& v = ssm.verdict(0);
        // S_p is never broken at the arm's speed without a STOP verdict that cycle (pfl: unless the
        // arm is within the limits worked out by hand for the default masses of every region below S_p)
        if (v.slack < 0.0 && !v.stop && !(r == SsmResponse::Pfl && v.robotSpeed <= kPflLimitsByHand[v.part])) ++unstopped;
        minSep = std::min(minSep, v.separation);
        // contacts by brute force: every person capsule against every arm capsule, the arm's speed
        // against the hand-worked limit of the region touched
        persons.pose(m.time());
        if (!persons.present(0) || v.robotSpeed <= 0.0) return;
        const auto body = bodyCapsules(persons.skeleton(0));
        for (int i = 0; i < m.capsuleCount(); ++i)
          for (int part = 0; part < kBodyParts; ++part)
            if (distance(m.movingCapsule(i).c, body[part]) <= 0.0) {
              ++touched;
              if (v.robotSpeed > kPflLimitsByHand[part]) ++touchedFast;
            }
      });
      EXPECT_EQ(unstopped, 0u) << name << " " << toString(r);
      EXPECT_EQ(o.contactsAboveLimit, 0u) << name << " " << toString(r);
      EXPECT_EQ(touchedFast, 0u) << name << " " << toString(r);
      EXPECT_EQ(touched > 0, o.contacts > 0) << name << " " << toString(r);
      if (r != SsmResponse::Pfl) {
        EXPECT_EQ(o.contacts, 0u) << name << " " << toString(r);
        EXPECT_GT(minSep, 0.2) << name << " " << toString(r);  // far from contact
      } else {
        EXPECT_EQ(o.contacts, o.contactsWithinLimit) << name;
      }
      EXPECT_EQ(o.cycles, cycles);
      progress[k++] = o.progress;
    }
    // scaling never does worse than the binary STOP; where the person works at the table it keeps
    // the arm going while binary STOP parks it
    EXPECT_GE(progress[1], progress[0]) << name;
    EXPECT_GE(progress[2], progress[1]) << name;  // contact within the limits instead of a stop: never slower
    for (int i = 0; i < 3; ++i) summed[i] += progress[i];
    for (double p : progress) EXPECT_LE(p, alone.progress + 1e-12) << name;
    if (std::string(name) != "person_walkpast") {
      EXPECT_GE(progress[1] / progress[0], 1.4) << name << " " << progress[0] << " " << progress[1];
    }
  }
  // the target over the study's cases (summed progress, as `stsim arm --study coexistence`
  // prints it): scaling completes the tasks >= 1.4x faster than binary STOP
  EXPECT_GE(summed[1] / summed[0], 1.4) << summed[0] << " " << summed[1];
}

// The clamped limits (quasi-static, mu = m_R) worked out by hand for the default masses (m_R =
// 10 kg) as in Pfl.ClampedAndMovingLimitsEqualAnnexAByHand: F / sqrt(10 K), per body part in
// bodyParts() order: head none; chest 140 / sqrt(250000); upper arm 150 / sqrt(300000); lower arm
// 160 / sqrt(400000); hand 140 / sqrt(750000); thigh 220 / sqrt(500000); lower leg 130 / sqrt(600000).
constexpr double kClampedByHand[kBodyParts] = {0.0, 0.28, 0.273861278752583, 0.252982212813470, 0.161658075373095,
                                               0.273861278752583, 0.252982212813470, 0.161658075373095,
                                               0.311126983722081, 0.167829278491384, 0.311126983722081, 0.167829278491384};

TEST(Pfl, ClosedLoopAtATableNoContactAboveItsLimit) {
  // person_reach with a table (a fixed box) between the person and the arm: the person stands
  // against it and reaches over it, so hands, arms and hips can be pinned. Every cycle the arm
  // runs below S_p under pfl, it is no faster than the limit of the regions below S_p, that limit
  // is never above the hand-worked one of the binding region (its clamped one where clamped), and
  // no contact (brute force, every capsule pair) is faster than the touched region's transient limit
  Scenario s = loadScenario(scenarioPath("person_reach"));
  Obstacle table;
  table.name = "table";
  table.kind = ShapeKind::Box;
  table.box.center = Vec3(1.05, 0.0, 0.35);
  table.box.halfExtents = Vec3(0.15, 0.6, 0.35);
  s.obstacles.push_back(table);
  std::uint64_t below = 0, clampedCycles = 0, pinnedCycles = 0, faster = 0, aboveByHand = 0, touchedFast = 0;
  PersonSet persons = makePersons(s);
  const CoexistenceOutcome o = runCoexistence(s, SsmResponse::Pfl, [&](const Monitor& m, const SeparationMonitor& ssm) {
    const SsmVerdict& v = ssm.verdict(0);
    if (v.slack < 0.0 && !v.stop) {
      ++below;
      if (v.clamped) ++clampedCycles;
      if (v.robotSpeed > v.pflLimit) ++faster;
      // the binding region pinned (by brute force: within clampGap of the table) or not
      persons.pose(m.time());
      const bool pinned = distance(bodyCapsules(persons.skeleton(0))[v.part], table.box) <= clampGap(s.ssm);
      if (v.pflLimit > (pinned ? kClampedByHand[v.part] : kPflLimitsByHand[v.part]) + 1e-12) ++aboveByHand;
      if (pinned) ++pinnedCycles;
    }
    persons.pose(m.time());
    if (!persons.present(0) || v.robotSpeed <= 0.0) return;
    const auto body = bodyCapsules(persons.skeleton(0));
    for (int i = 0; i < m.capsuleCount(); ++i)
      for (int part = 0; part < kBodyParts; ++part)
        if (distance(m.movingCapsule(i).c, body[part]) <= 0.0 && v.robotSpeed > kPflLimitsByHand[part]) ++touchedFast;
  });
  EXPECT_GT(below, 0u);
  EXPECT_GT(clampedCycles, 0u);  // the table does pin regions below S_p
  EXPECT_GT(pinnedCycles, 0u);   // the binding one among them
  EXPECT_EQ(faster, 0u);
  EXPECT_EQ(aboveByHand, 0u);
  EXPECT_EQ(touchedFast, 0u);
  EXPECT_EQ(o.contactsAboveLimit, 0u);
}

TEST(Ssm, AStoppedArmTravelsNoFartherThanSrPlusSs) {
  // independent of the formulae: from every STOP verdict of every response, the arm's
  // fastest end point's travel until the drive is at rest (its speed summed over the cycles)
  // against S_r + S_s of that cycle, which bound it by (3) and (4) with the drive's stopping time
  int stopsSeen = 0;
  for (const char* name : {"person_walkup", "person_walkpast", "person_reach"}) {
    const Scenario s = loadScenario(scenarioPath(name));
    for (SsmResponse r : {SsmResponse::Stop, SsmResponse::Scaling, SsmResponse::Pfl}) {
      double budget = -1.0, travel = 0.0;
      runCoexistence(s, r, [&](const Monitor& m, const SeparationMonitor& ssm) {
        const SsmVerdict& v = ssm.verdict(0);
        if (budget >= 0.0) {
          travel += v.robotSpeed * s.safety.cycleTime;
          if (v.robotSpeed == 0.0) {
            EXPECT_LE(travel, budget) << name << " " << toString(r) << " at " << m.time();
            budget = -1.0;
          }
        } else if (v.stop && v.robotSpeed > 0.0) {
          budget = v.terms.sr + v.terms.ss;
          travel = 0.0;
          ++stopsSeen;
        }
      });
    }
  }
  EXPECT_GT(stopsSeen, 0);
}

TEST(Person, CsvTraceIsInterpolatedBetweenLines) {
  auto row = [](double t, const Skeleton& s) {
    std::ostringstream r;
    r << t << ",worker";
    for (const Vec3& p : s.p) r << ',' << p.x() << ',' << p.y() << ',' << p.z();
    r << '\n';
    return r.str();
  };
  const fs::path csv = write("walk.csv", "# two readings of one person\n" + row(0.0, standingSkeleton(Vec3(2, 0, 0), M_PI)) +
                                             row(1.0, standingSkeleton(Vec3(1, 0, 0), M_PI)));
  const CsvPersonTrace trace(csv.string(), {"worker"});
  TracedPerson person(trace.rows(0));
  Skeleton s;
  EXPECT_FALSE(person.at(-0.5, s));  // before its first reading: not there
  ASSERT_TRUE(person.at(0.5, s));
  const Skeleton mid = standingSkeleton(Vec3(1.5, 0, 0), M_PI);
  for (int j = 0; j < kSkeletonJoints; ++j) EXPECT_LT((s.p[j] - mid.p[j]).norm(), 1e-6) << jointName(j);
  ASSERT_TRUE(person.at(5.0, s));  // after the last: stays
  EXPECT_NEAR(s.p[kPelvis].x(), 1.0, 1e-6);
  fs::remove(csv);
}

void expectError(const std::string& name, const std::string& yaml, const std::string& mention) {
  const fs::path p = write(name, yaml);
  try {
    const Scenario s = loadScenario(p.string());
    makePersons(s);
    ADD_FAILURE() << name << ": no error";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(mention), std::string::npos) << e.what();
    EXPECT_EQ(std::string(e.what()).find('\n'), std::string::npos) << e.what();
  }
  fs::remove(p);
}

TEST(Ssm, BadPersonInputIsNamed) {
  const std::string arm = "arms:\n  - {name: a, model: panda, waypoints: [{t: 0, q: [0, 0, 0, -1, 0, 1, 0]}]}\n";
  expectError("fast.yaml", arm + "persons:\n  - {name: p, start: {xy: [2, 0]}, script: [{walk: {to: [1, 0], speed: 3}}]}\n",
              ":4: persons[0].script[0].walk.speed: 3 m/s is beyond ssm.body_speed 1.6 m/s");
  expectError("resp.yaml", arm + "ssm: {response: maybe}\n", ":3: ssm.response: must be one of stop, scaling, pfl, got 'maybe'");
  expectError("payload.yaml", arm + "ssm: {response: pfl, payload: -1}\n", ":3: ssm.payload: must not be negative, got -1");
  expectError("mass.yaml", arm + "ssm: {response: pfl, arm_mass: 0}\n", ":3: ssm.arm_mass: must be positive");
  // the keys read: (b)'s masses give (b)'s hand limit worked out by hand above
  const fs::path ok = write("pfl.yaml", arm + "ssm: {response: pfl, arm_mass: 30, payload: 5}\n");
  const Scenario s = loadScenario(ok.string());
  EXPECT_EQ(s.ssm.response, SsmResponse::Pfl);
  EXPECT_NEAR(pflSpeedLimit(s.ssm, BodyRegion::Hand), 1.33958534214468, 1e-9);
  fs::remove(ok);
  expectError("nostart.yaml", arm + "persons:\n  - {name: p, script: []}\n", "persons[0].start: missing");
  expectError("hand.yaml", arm + "persons:\n  - {start: {xy: [2, 0]}, script: [{reach: {hand: third, to: [1, 0, 1], speed: 1}}]}\n",
              "persons[0].script[0].reach.hand: expected right or left");
  expectError("jitter.yaml", arm + "persons:\n  - {start: {xy: [2, 0]}, sensor: {period: 0.033, jitter: 0.05}}\n",
              "persons[0].sensor.jitter: must be at least 0 and less than the period");
  const fs::path csv = write("trace.csv", "t,person\n0,p\n");
  expectError("traced.yaml", arm + "persons:\n  - {name: p, trace: " + csv.string() + "}\n", csv.string() + ":2: expected t, person");
  fs::remove(csv);
}

}  // namespace
}  // namespace st::arm

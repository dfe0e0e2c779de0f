// Persons as foes: a pedestrian's body and class from SUMO's conventions, its conflicts typed
// apart at any angle, and a car meeting a person on a crosswalk worked out by hand (TTC, PET),
// through the warnings and through conflicts.csv's book; FCD persons read as the live run reads
// them (a passenger nested in its vehicle is no foe).
#include <gtest/gtest.h>

#include <unistd.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include <sthighway/conflict.hpp>
#include <sthighway/monitor.hpp>
#include <sthighway/sumo_conversion.hpp>
#include <sthighway/sumo_files.hpp>

#include "roads.hpp"

namespace st::highway {
namespace {

constexpr double kPi = 3.14159265358979323846;

TEST(Pedestrians, ClassesAndBodiesFromSumoNames) {
  EXPECT_EQ(vehicleClassFromName("pedestrian"), VehicleClass::Pedestrian);
  EXPECT_EQ(vehicleClassFromName("bicycle"), VehicleClass::Bicycle);
  EXPECT_STREQ(toString(VehicleClass::Pedestrian), "pedestrian");
  EXPECT_STREQ(toString(VehicleClass::Bicycle), "bicycle");
  // SUMO 1.15's defaults for a vType of the class that sets no size (read back through TraCI)
  const VehicleTypeInfo p = defaultPersonType();
  EXPECT_EQ(p.vehicleClass, VehicleClass::Pedestrian);
  EXPECT_DOUBLE_EQ(p.length, 0.215);
  EXPECT_DOUBLE_EQ(p.width, 0.478);
  EXPECT_DOUBLE_EQ(p.mass, 70.0);
  SumoTypeRecord bicycle;
  bicycle.vClass = "bicycle";
  const VehicleTypeInfo b = toVehicleTypeInfo(bicycle);
  EXPECT_EQ(b.vehicleClass, VehicleClass::Bicycle);
  EXPECT_DOUBLE_EQ(b.length, 1.6);
  EXPECT_DOUBLE_EQ(b.mass, 90.0);
  EXPECT_DOUBLE_EQ(b.decel, 3.0);
  // a pedestrian's conflict is its own type at every angle; others keep SSAM's classes
  const ConflictConfig cfg;
  for (double deg : {0.0, 45.0, 90.0, 180.0}) {
    EXPECT_EQ(conflictType(deg, VehicleClass::Passenger, VehicleClass::Pedestrian, cfg), ConflictType::Pedestrian);
    EXPECT_EQ(conflictType(deg, VehicleClass::Pedestrian, VehicleClass::Truck, cfg), ConflictType::Pedestrian);
    EXPECT_EQ(conflictType(deg, VehicleClass::Bicycle, VehicleClass::Passenger, cfg), conflictType(deg, cfg));
  }
  EXPECT_TRUE(isConflictType(ConflictType::Pedestrian));
  EXPECT_FALSE(isSsamType(ConflictType::Pedestrian));  // SUMO's SSM sees no persons
}

// A car (5 m x 1.8 m) drives east at 10 m/s along y = 0 from x = -30; a person (SUMO's 0.215 m x
// 0.478 m) walks north across its path at 1.5 m/s from y = -5, stops at t = 1.5 s (y = -2.75,
// short of the car's side at -0.9) and walks on at t = 3.5 s.
// Until 1.5 s on a collision course: the car's front reaches the person's far side (x = -0.239)
// at (30 - 2.5 - 0.239) / 10 = 2.7261 s while the person's front (y - 0.9 + 0.1075 >= 0) is in
// the car's strip from 2.6617 s on: TTC 2.7261 - t, least at 1.5 s: 1.2261 s.
// PET across the swept area: the car's centre leaves it 2.5 + 0.239 m past x = 0 at 3.2739 s;
// the person's centre enters it 0.9 + 0.1075 m before y = 0, at 3.5 + (2.75 - 1.0075) / 1.5 =
// 4.661667 s: PET 1.387767 s.
struct Crosswalk {
  std::vector<Warning> warnings;
  std::vector<Conflict> conflicts;
};
void collect(HighwayMonitor& m, Crosswalk& out) {
  for (Warning& w : m.takeFinished()) out.warnings.push_back(std::move(w));
  std::vector<Conflict> conflicts;
  m.takeConflicts(conflicts);
  out.conflicts.insert(out.conflicts.end(), conflicts.begin(), conflicts.end());
}
Crosswalk crossAtAWalk(Prediction prediction) {
  auto personY = [](double t) { return t <= 1.5 ? -5.0 + 1.5 * t : t <= 3.5 ? -2.75 : -2.75 + 1.5 * (t - 3.5); };
  MonitorConfig cfg;
  cfg.detector.kind = DetectorKind::Box;
  cfg.prediction = prediction;
  cfg.broadphase = Broadphase::AllPairs;
  cfg.checkRoad = false;
  HighwayMonitor m(oneLaneRoad(), cfg);
  Crosswalk out;
  double t = 0.0;
  for (int k = 0; k <= 60; ++k) {
    t = 0.1 * k;
    VehicleState car;
    car.id = "car";
    car.handle = 0;
    car.position = Vec2(-30.0 + 10.0 * t, 0.0);
    car.speed = 10.0;
    VehicleState person;
    person.id = "ped";
    person.handle = 1;
    person.vehicleClass = VehicleClass::Pedestrian;
    person.length = 0.215;
    person.width = 0.478;
    person.mass = 70.0;
    person.equipped = false;
    person.heading = 0.5 * kPi;
    person.position = Vec2(0.0, personY(t));
    const bool walking = t <= 1.5 + 1e-9 || t > 3.5 + 1e-9;
    person.speed = walking ? 1.5 : 0.0;
    m.step(t, std::vector<VehicleState>{car, person});
    collect(m, out);
  }
  m.finish(t + 0.1);
  collect(m, out);
  return out;
}

TEST(Pedestrians, CarMeetsAPersonOnACrosswalkByHand) {
  for (Prediction prediction : {Prediction::Straight, Prediction::Road}) {
    const Crosswalk r = crossAtAWalk(prediction);
    ASSERT_EQ(r.warnings.size(), 1u) << "the person is not equipped: only the car is warned";
    const Warning& w = r.warnings[0];
    EXPECT_EQ(w.ego, "car");
    EXPECT_EQ(w.foe, "ped");
    EXPECT_EQ(w.type, ConflictType::Pedestrian);
    EXPECT_NEAR(w.minTtc, 2.7261 - 1.5, 1e-9);
    EXPECT_NEAR(w.minTtcTime, 1.5, 1e-9);
    EXPECT_NEAR(w.end, 1.6, 1e-9);  // the person stopped short: no collision course from 1.6 s on
    EXPECT_NEAR(w.pet, 4.661667 - 3.2739, 1e-6);
    // conflicts.csv: the same encounter once, below TTC* 1.5 s; SSAM's first is the person, in the
    // car's strip (2.6617 s) before the car's front reaches it (2.7261 s)
    ASSERT_EQ(r.conflicts.size(), 1u);
    const Conflict& c = r.conflicts[0];
    EXPECT_EQ(c.type, ConflictType::Pedestrian);
    EXPECT_EQ(c.first, "ped");
    EXPECT_EQ(c.second, "car");
    EXPECT_NEAR(c.minTtc, 2.7261 - 1.5, 1e-9);
    EXPECT_NEAR(c.pet, 4.661667 - 3.2739, 1e-6);
  }
}

TEST(Pedestrians, FcdPersonsOnFootAreFoesAndPassengersAreNot) {
  const auto path = std::filesystem::temp_directory_path() / ("stsim_persons_" + std::to_string(::getpid()) + ".xml");
  {
    std::ofstream f(path);
    f << "<fcd-export>\n"
         "<timestep time=\"0.00\">\n"
         "  <vehicle id=\"bus\" x=\"10\" y=\"0\" angle=\"90\" type=\"DEFAULT_VEHTYPE\" speed=\"5\" lane=\"e_0\">\n"
         "    <person id=\"rider\" x=\"10\" y=\"0\" angle=\"90\" speed=\"5\" pos=\"3\" edge=\"e\" slope=\"0\"/>\n"
         "  </vehicle>\n"
         "  <person id=\"ped\" x=\"0\" y=\"-3\" angle=\"0\" speed=\"1.2\" pos=\"4\" edge=\":C_c0\" slope=\"0\"/>\n"
         "</timestep>\n"
         "<timestep time=\"0.10\">\n"
         "  <person id=\"bus\" x=\"0\" y=\"-2.88\" angle=\"0\" speed=\"1.2\" pos=\"4\" edge=\":C_c0\" slope=\"0\"/>\n"
         "</timestep>\n"
         "</fcd-export>\n";
  }
  FcdReader reader(path);
  FcdFrame frame;
  ASSERT_TRUE(reader.next(frame));
  ASSERT_EQ(frame.vehicles.size(), 2u);
  EXPECT_EQ(frame.vehicles[0].id, "bus");
  const VehicleState& p = frame.vehicles[1];
  EXPECT_EQ(p.id, "ped");
  EXPECT_EQ(p.vehicleClass, VehicleClass::Pedestrian);
  EXPECT_DOUBLE_EQ(p.length, 0.215);
  EXPECT_DOUBLE_EQ(p.width, 0.478);
  EXPECT_EQ(p.lane, -1);
  EXPECT_NEAR(p.heading, 0.5 * kPi, 1e-12);  // SUMO's 0 degrees: north
  EXPECT_NEAR(p.position.y(), -3.0 - 0.5 * 0.215, 1e-12);  // centre behind the front, as for vehicles
  EXPECT_NE(p.handle, frame.vehicles[0].handle);
  // a person named like a vehicle is another road user: its own handle
  ASSERT_TRUE(reader.next(frame));
  ASSERT_EQ(frame.vehicles.size(), 1u);
  EXPECT_EQ(frame.vehicles[0].vehicleClass, VehicleClass::Pedestrian);
  EXPECT_EQ(frame.vehicles[0].handle, 2);
  EXPECT_FALSE(reader.next(frame));
  std::filesystem::remove(path);
}

}  // namespace
}  // namespace st::highway

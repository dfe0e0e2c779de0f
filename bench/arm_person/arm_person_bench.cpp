// Speed and separation monitoring per cycle (ISO/TS 15066 S_p for every person capsule against
// every arm capsule) beside the collision monitor's own cycle, on person_walkup's nominal motion
// (one Panda, 10 001 cycles at 1 kHz, open loop so every pass does the same work), with 1 and 4
// persons. Compares against: the collision cycle of the same run, and the 1 ms cycle (the
// issue's target: one arm and one person, monitor p99 <= 100 us). Prints a table.
//   arm_person_bench [passes]
#include <algorithm>
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <vector>

#include <starm/study.hpp>

using namespace st;
using namespace st::arm;
using Clock = std::chrono::steady_clock;

namespace {

double us(Clock::time_point a, Clock::time_point b) { return std::chrono::duration<double, std::micro>(b - a).count(); }

struct Row {
  std::vector<double> monitor, ssm, total;
};

Row runOnce(const Scenario& sc, int persons) {
  Monitor m = makeMonitor(sc);
  auto src = makeSensor(sc);
  PersonSet set;
  for (int p = 0; p < persons; ++p) {
    PersonScript s = sc.persons.at(0).script;
    s.start.y() += 0.6 * p;  // side by side along the table
    for (PersonAction& a : s.actions) a.to.y() += 0.6 * p;
    std::string name = "p";
    name += std::to_string(p);
    set.add(name, std::make_unique<ScriptedPerson>(s));
  }
  SeparationMonitor ssm(sc.ssm, m.armCount());
  Row row;
  Reading r;
  bool have = src->next(r);
  while (have) {
    const double t = r.t;
    const auto t0 = Clock::now();
    while (have && r.t == t) {
      m.setJointState(r.arm, r.t, r.q.data(), r.qdot.data());
      have = src->next(r);
    }
    m.cycle(t);
    const auto t1 = Clock::now();
    separationStep(m, set, ssm, nullptr);
    const auto t2 = Clock::now();
    row.monitor.push_back(us(t0, t1));
    row.ssm.push_back(us(t1, t2));
    row.total.push_back(us(t0, t2));
  }
  return row;
}

}  // namespace

int main(int argc, char** argv) {
  const int passes = argc > 1 ? std::max(1, std::atoi(argv[1])) : 5;
  const Scenario sc = loadScenario(std::string(STSIM_SOURCE_DIR) + "/models/arm/scenarios/person_walkup.yaml");
  std::printf("speed and separation monitoring, person_walkup (1 Panda, %s), %d passes; per cycle, us\n\n",
              "10 001 cycles at 1 kHz", passes);
  std::printf("| persons | collision cycle p50 / p99 | SSM p50 / p99 | monitor + SSM p50 / p99 / max | SSM / collision p50 | "
              "p99 / 1 ms budget |\n|---|---|---|---|---|---|\n");
  for (int persons : {1, 4}) {
    Row all;
    for (int p = 0; p < passes; ++p) {
      Row r = runOnce(sc, persons);
      all.monitor.insert(all.monitor.end(), r.monitor.begin(), r.monitor.end());
      all.ssm.insert(all.ssm.end(), r.ssm.begin(), r.ssm.end());
      all.total.insert(all.total.end(), r.total.begin(), r.total.end());
    }
    const double mx = *std::max_element(all.total.begin(), all.total.end());
    std::printf("| %d | %.2f / %.2f | %.2f / %.2f | %.2f / %.2f / %.0f | %.1fx | %.3f |\n", persons,
                percentile(all.monitor, 50), percentile(all.monitor, 99), percentile(all.ssm, 50), percentile(all.ssm, 99),
                percentile(all.total, 50), percentile(all.total, 99), mx,
                percentile(all.ssm, 50) / percentile(all.monitor, 50), percentile(all.total, 99) / 1000.0);
  }
  return 0;
}

#include <starm/study.hpp>

#include <algorithm>
#include <cmath>
#include <limits>
#include <random>

namespace st::arm {

namespace {

// own uniform mapping: deterministic across standard libraries
struct Uniform {
  std::mt19937_64 gen;
  double operator()(double lo, double hi) { return lo + (hi - lo) * (static_cast<double>(gen() >> 11) * 0x1.0p-53); }
};

}  // namespace

Scenario randomCourse(std::uint64_t seed, int index) {
  Uniform u{std::mt19937_64(seed * 1000003u + static_cast<std::uint64_t>(index))};
  Scenario s;
  s.file = "random:" + std::to_string(seed) + "/" + std::to_string(index);
  s.safety = SafetyConfig{};
  s.broad.kind = SpaceKind::Tree;
  s.broad.rule.maxDepth = 4;
  s.broad.depthFromScene = false;
  s.broad.margin = 0.03;
  const double gap = u(0.85, 1.3), side = u(-0.12, 0.12);
  const std::vector<double> home{0, -0.785, 0, -2.356, 0, 1.571, 0.785};
  for (int a = 0; a < 2; ++a) {
    ArmInstance inst{a == 0 ? "left" : "right", pandaModel(), Eigen::Isometry3d::Identity()};
    if (a == 1) {
      inst.base.translation() = Vec3(gap, side, 0.0);
      inst.base.linear() = Eigen::AngleAxisd(3.141592653589793, Vec3::UnitZ()).toRotationMatrix();
    }
    Script sc;
    sc.arm = a;
    sc.where = s.file + ": arms[" + std::to_string(a) + "].waypoints";
    std::vector<double> start = home, goal{u(-0.3, 0.3), u(0.15, 0.7), u(-0.3, 0.3), u(-1.7, -0.9),
                                           u(-0.3, 0.3), u(1.3, 2.0), u(0.0, 1.5)};
    for (int k = 0; k < 7; ++k) start[k] += u(-0.15, 0.15);
    const double t0 = u(0.0, 0.5), t1 = t0 + u(1.2, 2.4);
    sc.waypoints = {{0.0, start}, {t0, start}, {t1, goal}};
    s.scripts.push_back(sc);
    s.arms.push_back(std::move(inst));
  }
  s.duration = 3.0;
  followDefaults(s);  // braking as the safety terms, as a scenario file without braking:
  return s;
}

CourseOutcome runCourse(const Scenario& s, bool closedLoop) {
  Monitor m = makeMonitor(s);
  std::unique_ptr<SensorSource> open;
  std::unique_ptr<ClosedLoopSensor> closed;
  if (closedLoop) closed = makeClosedLoopSensor(s);
  else open = makeSensor(s);
  SensorSource& src = closedLoop ? static_cast<SensorSource&>(*closed) : *open;
  CourseOutcome out;
  out.minDistance = std::numeric_limits<double>::infinity();
  RunStats st;
  run(m, src, st, [&](const Monitor& mon) {
    if (closed) closed->observe(mon, mon.time());
    const Warning& n = mon.nearest();
    if (n.arm < 0) return;
    out.minDistance = std::min(out.minDistance, n.distance);
    if (!out.contact && n.distance <= 0.0) {
      out.contact = true;
      out.firstContact = n.t;
      out.contactWithMoving = n.obstacle >= 0 && mon.obstacles()[n.obstacle].moving();
    }
  });
  out.cycles = st.cycles;
  out.stops = m.counters().stops;
  return out;
}

StudyResult stoppingStudy(const StudyConfig& cfg) {
  StudyResult res;
  std::vector<Scenario> courses;
  for (const std::string& f : cfg.shipped) courses.push_back(loadScenario(f));
  const std::size_t nShipped = courses.size();
  for (int i = 0; i < cfg.randomCourses; ++i) courses.push_back(randomCourse(cfg.seed, i));
  // open loop does not depend on the safe time: once per course
  std::vector<CourseOutcome> open;
  for (const Scenario& s : courses) open.push_back(runCourse(s, false));
  for (std::size_t i = nShipped; i < courses.size(); ++i) res.randomContactsOpen += open[i].contact ? 1 : 0;
  for (std::size_t i = 0; i < nShipped; ++i) {
    ShippedRow r;
    r.name = courses[i].file;
    r.safeTime = courses[i].safety.safeTime();
    r.open = open[i];
    r.closed = runCourse(courses[i], true);
    res.shipped.push_back(r);
  }
  for (double assumed : cfg.assumedStopping) {
    StudyRow row;
    row.assumedStopping = assumed;
    std::vector<double> mins;
    for (std::size_t i = 0; i < courses.size(); ++i) {
      Scenario s = courses[i];
      s.safety.stoppingTime = assumed;
      if (s.safety.horizon != 0.0) s.safety.horizon = std::max(s.safety.horizon, s.safety.safeTime());
      s.braking.stoppingTime = cfg.stoppingTime;
      s.braking.deceleration = 0.0;
      s.braking.resumeAfter = std::numeric_limits<double>::infinity();
      row.safeTime = s.safety.safeTime();
      row.needed = cfg.stoppingTime + s.braking.delay + s.safety.cycleTime;
      const CourseOutcome c = runCourse(s, true);
      ++row.courses;
      row.contactsOpen += open[i].contact ? 1 : 0;
      if (c.contact) {
        ++row.contactsClosed;
        if (c.contactWithMoving) ++row.contactsClosedMoving;
        if (row.failures.size() < 5) row.failures.push_back(s.file);
      }
      mins.push_back(c.minDistance);
    }
    std::sort(mins.begin(), mins.end());
    row.minDistanceClosed = mins.empty() ? 0.0 : mins.front();
    row.medianMinDistanceClosed = mins.empty() ? 0.0 : mins[mins.size() / 2];
    res.rows.push_back(row);
  }
  return res;
}

void separationStep(const Monitor& m, PersonSet& persons, SeparationMonitor& ssm, ClosedLoopSensor* drive) {
  persons.pose(m.time());
  if (drive)
    for (int a = 0; a < m.armCount(); ++a) ssm.setDrive(a, &drive->drive(a));
  ssm.cycle(m, persons);
  if (drive) drive->observe(m, m.time(), &ssm);
}

CoexistenceOutcome runCoexistence(Scenario s, SsmResponse response,
                                  const std::function<void(const Monitor&, const SeparationMonitor&)>& onCycle) {
  s.ssm.response = response;
  Monitor m = makeMonitor(s);
  std::unique_ptr<ClosedLoopSensor> drive = makeClosedLoopSensor(s);
  PersonSet persons = makePersons(s);
  SeparationMonitor ssm(s.ssm, m.armCount());
  CoexistenceOutcome o;
  o.minSlack = std::numeric_limits<double>::infinity();
  RunStats stats;
  run(m, *drive, stats, [&](const Monitor& mm) {
    separationStep(mm, persons, ssm, drive.get());
    for (int a = 0; a < mm.armCount(); ++a) {
      const SsmVerdict& v = ssm.verdict(a);
      if (v.person >= 0) o.minSlack = std::min(o.minSlack, v.slack);
    }
    if (onCycle) onCycle(mm, ssm);
  });
  const SsmCounters& c = ssm.counters();
  o.cycles = stats.cycles;
  o.contacts = c.contacts;
  o.contactsWithinLimit = c.contactsWithinLimit;
  o.contactsAboveLimit = c.contactsAboveLimit;
  o.pflCycles = c.pflCycles;
  o.violations = c.violations;
  o.stopCycles = c.stopCycles;
  o.scaledCycles = c.scaledCycles;
  o.minSeparation = c.minSeparation;
  o.duration = m.time();
  double tau = 0.0;
  for (int a = 0; a < m.armCount(); ++a) {
    o.stops += drive->drive(a).stops();
    tau += drive->drive(a).tau();
  }
  o.progress = o.duration > 0.0 ? tau / m.armCount() / o.duration : 1.0;
  return o;
}

CoexistenceOutcome runWithoutPersons(Scenario s) {
  s.persons.clear();
  return runCoexistence(std::move(s), SsmResponse::Scaling);
}

}  // namespace st::arm

#include <stpool/game.hpp>

#include <cmath>
#include <stdexcept>
#include <string>

#include <stcore/tolerances.hpp>

namespace st::pool {

const char* toString(PoolEventKind k) {
  switch (k) {
    case PoolEventKind::Ball: return "ball";
    case PoolEventKind::Cushion: return "cushion";
    case PoolEventKind::Jaw: return "jaw";
    case PoolEventKind::Pocket: return "pocket";
    case PoolEventKind::Boundary: return "boundary";
    case PoolEventKind::Rest: return "rest";
    case PoolEventKind::Strike: return "strike";
    case PoolEventKind::Stop: return "stop";
    case PoolEventKind::Count: break;
  }
  return "?";
}

const char* toString(ShotEnd e) {
  switch (e) {
    case ShotEnd::Rest: return "rest";
    case ShotEnd::TimeLimit: return "time-limit";
    case ShotEnd::Stopped: return "stopped";
  }
  return "?";
}

SimulatorConfig simulatorConfig(const SpaceSpec& space, const TableSpec& table, const std::vector<BallSpec>& balls) {
  SimulatorConfig c;
  c.spaceKind = space.kind;
  c.rule.decompositionFactor = space.decompositionFactor;
  c.rule.autoFactor = space.autoFactor;
  c.rule.divisions = space.divisions;
  c.rule.cellSize = space.cellSize;
  c.marginFactor = space.marginFactor();
  c.rule.maxDepth = space.maxDepth;
  if (c.rule.maxDepth < 0) {
    double rmax = kBallRadius;
    for (const auto& b : balls) rmax = std::max(rmax, b.radius);
    const Rect box = makeTable(table).bounds();
    // each division halves the longest side (4 divisions halve both)
    const double extent = box.extent().maxCoeff();
    int depth = 0;
    while (depth < 30 && extent / std::ldexp(1.0, depth + 1) >= 2.0 * rmax) ++depth;
    c.rule.maxDepth = space.divisions == 2 ? 2 * depth : depth;
  }
  return c;
}

SimulatorConfig simulatorConfig(const Scenario& s) { return simulatorConfig(s.space, s.table, s.balls); }

Game::Game(const Scenario& scenario, const SimulatorConfig& config)
    : table_(makeTable(scenario.table)), specs_(scenario.balls), sim_(table_.bounds(), config),
      friction_(scenario.friction) {
  validateScenario(scenario, scenario.name);
  for (const Segment& c : table_.cushions) sim_.addSegment(c);
  for (const auto& p : table_.pockets) sim_.addSensor(p);
  for (const BallSpec& b : specs_) {
    const int i = sim_.addBall(b.position, b.velocity, b.radius, b.mass, b.number);
    if (friction_ > 0.0) sim_.setDeceleration(i, friction_);
  }
}

int Game::handleOf(int number) const {
  for (int i = 0; i < static_cast<int>(specs_.size()); ++i)
    if (specs_[i].number == number) return i;
  return -1;
}

bool Game::atRest() const {
  for (const auto& b : sim_.balls())
    if (b.active && b.v.squaredNorm() > 0.0) return false;
  return true;
}

void Game::strike(const Shot& shot) {
  const int i = handleOf(shot.ball);
  if (i < 0) throw std::runtime_error("shot " + std::to_string(shots_ + 1) + ": no ball number " + std::to_string(shot.ball));
  if (!sim_.ball(i).active)
    throw std::runtime_error("shot " + std::to_string(shots_ + 1) + ": ball " + std::to_string(shot.ball) +
                             " was pocketed");
  sim_.setVelocity(i, shot.velocity);
}

void Game::checkOnTable(int ball, double t) const {
  const Rect box = table_.bounds();
  const Vec2 p = sim_.ball(ball).positionAt(t);
  // a centre may touch the bounds (a ball in a pocket mouth), never pass them by more than the slop
  constexpr double kRoom = 1e3 * tol::kLinearSlop;
  if ((p.array() >= box.min.array() - kRoom).all() && (p.array() <= box.max.array() + kRoom).all()) return;
  std::string msg = "shot ";
  msg.append(std::to_string(shots_ + 1)).append(": ball ").append(std::to_string(specs_[ball].number));
  msg.append(" left the table at t = ").append(std::to_string(t)).append(" s (a missed cushion: numerical failure)");
  throw std::runtime_error(msg);
}

PoolEvent Game::manual(PoolEventKind kind, int ball) const {
  PoolEvent e;
  e.shot = shots_;
  e.t = sim_.now();
  e.kind = kind;
  e.ball = ball;
  e.p = sim_.ball(ball).positionAt(e.t);
  e.v = sim_.ball(ball).velocityAt(e.t);
  return e;
}

PoolEvent Game::translate(const EventRecord& r) const {
  PoolEvent e;
  e.shot = shots_;
  e.t = r.t;
  e.ball = r.a;
  e.other = r.b;
  const BallState<2>& a = sim_.ball(r.a);
  e.p = a.positionAt(r.t);
  e.v = a.velocityAt(r.t);
  switch (r.kind) {
    case EventKind::BallBall: {
      e.kind = PoolEventKind::Ball;
      const BallState<2>& b = sim_.ball(r.b);
      e.otherP = b.positionAt(r.t);
      e.otherV = b.velocityAt(r.t);
      break;
    }
    case EventKind::BallSegment: {
      // the segment kernel also reports contacts with a cushion's end points: those are the jaws
      const Segment& s = table_.cushions[r.b];
      const double u = (e.p - s.a).dot(s.direction()) / s.direction().squaredNorm();
      e.kind = (u <= 0.0 || u >= 1.0) ? PoolEventKind::Jaw : PoolEventKind::Cushion;
      break;
    }
    case EventKind::BallPoint: e.kind = PoolEventKind::Jaw; break;
    case EventKind::BallWall: e.kind = PoolEventKind::Cushion; break;
    case EventKind::Sensor: e.kind = PoolEventKind::Pocket; break;
    case EventKind::Boundary: e.kind = PoolEventKind::Boundary; break;
    case EventKind::Rest: e.kind = PoolEventKind::Rest; break;
    case EventKind::Model:  // the pool game schedules none
    case EventKind::Count: break;
  }
  return e;
}

}  // namespace st::pool

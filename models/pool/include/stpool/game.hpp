#pragma once
// A game of pool on the stcore simulator: the table's cushions and pockets, the balls, and shots
// played one after another (§2.1: "impart force again and continue").
#include <chrono>
#include <cstdint>
#include <exception>
#include <optional>
#include <string>
#include <vector>

#include <stcore/simulator.hpp>
#include <stpool/ball.hpp>
#include <stpool/scenario.hpp>
#include <stpool/table.hpp>

namespace st::pool {

// What the pool sees: a simulator event named in table terms.
enum class PoolEventKind : std::uint8_t {
  Ball,      // two balls collide
  Cushion,   // a ball bounces off a cushion's face
  Jaw,       // a ball strikes a pocket jaw (a cushion's end point)
  Pocket,    // a ball is pocketed and leaves the table
  Boundary,  // a ball crosses the boundary of its region of space (version II bookkeeping)
  Rest,      // a ball slowed by friction comes to a stop
  Strike,    // the cue gives a ball its velocity (start of a shot; not a simulator event)
  Stop,      // a shot's time limit stops a moving ball where it stands (not a simulator event)
  Count
};
const char* toString(PoolEventKind k);

struct PoolEvent {
  int shot = 0;
  double t = 0.0;            // s since the first shot
  PoolEventKind kind = PoolEventKind::Ball;
  int ball = -1;             // handle (index into the scenario's balls)
  int other = -1;            // other ball's handle, cushion index or pocket index; -1 if none
  Vec2 p = Vec2::Zero();     // ball's centre at t
  Vec2 v = Vec2::Zero();     // ball's velocity just after the event
  Vec2 otherP = Vec2::Zero();  // other ball's centre and velocity (Ball events only)
  Vec2 otherV = Vec2::Zero();
};

// Stopped: the observer stopped the shot (an event limit, Ctrl-C) before rest or its time limit.
enum class ShotEnd { Rest, TimeLimit, Stopped };
const char* toString(ShotEnd e);

struct ShotSummary {
  int index = 0;
  int ball = 0;              // struck ball's number (-1: no strike)
  double start = 0.0, end = 0.0;  // s
  ShotEnd ending = ShotEnd::TimeLimit;
  double keStart = 0.0;      // J, just after the strike
  double keEnd = 0.0;        // J, of the balls still on the table at the end (before they are stopped)
  double kePocketed = 0.0;   // J carried into pockets during the shot
  Vec2 momentumStart = Vec2::Zero(), momentumEnd = Vec2::Zero();  // kg m/s
  std::uint64_t events = 0;
  bool friction = false;     // energy is dissipated: the drift below is then the lost fraction
  // (keEnd + kePocketed - keStart) / keStart: zero for an exact frictionless simulation
  double energyDrift() const { return keStart > 0.0 ? (keEnd + kePocketed - keStart) / keStart : 0.0; }
};

struct Pocketing {
  int ball = -1;    // handle
  int number = 0;
  int pocket = -1;
  int shot = 0;
  double t = 0.0;
};

class Game {
 public:
  // Throws std::invalid_argument if the scenario cannot be built (see validateScenario).
  Game(const Scenario& scenario, const SimulatorConfig& config);

  // Strikes shot.ball and runs until rest or the shot's time limit `limit` (s after the strike);
  // on a time limit every ball is stopped where it stands (§2.1.1). Calls observer(const PoolEvent&)
  // for each event. Throws std::runtime_error if the shot's ball is not on the table.
  template <class Observer>
  ShotSummary play(const Shot& shot, double limit, Observer&& observer) {
    return runShot(&shot, limit, observer);
  }
  ShotSummary play(const Shot& shot, double limit) {
    return runShot(&shot, limit, [](const PoolEvent&) {});
  }
  // The same without a strike: the balls move with the velocities they have (a scenario without shots).
  template <class Observer>
  ShotSummary coast(double limit, Observer&& observer) {
    return runShot(nullptr, limit, observer);
  }

  const Table& table() const { return table_; }
  const std::vector<BallSpec>& specs() const { return specs_; }
  const Simulator<2>& simulator() const { return sim_; }
  const std::vector<Pocketing>& pocketed() const { return pocketed_; }
  double friction() const { return friction_; }  // m/s^2
  int shotsPlayed() const { return shots_; }
  // The shot the observer stopped by throwing (ending Stopped, its energies and momenta at the
  // stop), if the last shot ended that way; a run's record keeps it like any other shot.
  const std::optional<ShotSummary>& stoppedShot() const { return stopped_; }
  // Handle of the ball with this number, or -1.
  int handleOf(int number) const;
  // True when nothing moves: every ball pocketed or still.
  bool atRest() const;

 private:
  PoolEvent translate(const EventRecord& e) const;
  template <class Observer>
  ShotSummary runShot(const Shot* shot, double limit, Observer&& observer);
  PoolEvent manual(PoolEventKind kind, int ball) const;
  void strike(const Shot& shot);
  // Integrity check: throws std::runtime_error if ball's centre at t is off the table (outside
  // its bounds, pocket mouths included). Cannot happen with sane input; it catches a missed
  // cushion (e.g. speeds the clock cannot resolve) instead of letting a ball fly off silently.
  void checkOnTable(int ball, double t) const;

  Table table_;
  std::vector<BallSpec> specs_;
  Simulator<2> sim_;
  std::vector<Pocketing> pocketed_;
  double friction_ = 0.0;
  int shots_ = 0;
  std::optional<ShotSummary> stopped_;
};

// Wall-clock seconds of a callable; for summaries, never for results.
template <class F>
double wallSeconds(F&& f) {
  const auto t0 = std::chrono::steady_clock::now();
  f();
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// The simulator configuration a scenario's space section asks for. An automatic max depth stops
// subdividing where a region would be narrower than the largest ball: finer regions cannot
// separate two touching balls, and with df 1 or 2 a tight rack would otherwise be split down
// to stcore's default depth around every contact.
SimulatorConfig simulatorConfig(const SpaceSpec& space, const TableSpec& table, const std::vector<BallSpec>& balls);
SimulatorConfig simulatorConfig(const Scenario& scenario);

// ---- inline templates -------------------------------------------------------------------------

template <class Observer>
ShotSummary Game::runShot(const Shot* shot, double limit, Observer&& observer) {
  ShotSummary s;
  s.index = shots_;
  s.friction = friction_ > 0.0;
  s.ball = shot ? shot->ball : -1;
  s.start = sim_.now();
  if (shot) {
    strike(*shot);
    observer(manual(PoolEventKind::Strike, handleOf(shot->ball)));
  }
  s.keStart = sim_.kineticEnergy();
  s.momentumStart = sim_.momentum();
  stopped_.reset();
  // the observer may stop the shot by throwing: its summary so far is kept for the record
  struct KeepIfStopped {
    Game& game;
    ShotSummary& s;
    int uncaught = std::uncaught_exceptions();
    ~KeepIfStopped() {
      if (std::uncaught_exceptions() <= uncaught) return;
      s.ending = ShotEnd::Stopped;
      s.end = game.sim_.now();
      s.keEnd = game.sim_.kineticEnergy();
      s.momentumEnd = game.sim_.momentum();
      game.stopped_ = s;
      ++game.shots_;
    }
  } keep{*this, s};
  const StopReason why = sim_.run(s.start + limit, [&](const EventRecord& r) {
    const PoolEvent e = translate(r);
    if (e.kind != PoolEventKind::Pocket) checkOnTable(e.ball, e.t);
    if (e.kind == PoolEventKind::Pocket) {
      const BallState<2>& b = sim_.ball(e.ball);
      s.kePocketed += 0.5 * b.mass * b.velocityAt(e.t).squaredNorm();
      pocketed_.push_back(Pocketing{e.ball, specs_[e.ball].number, e.other, shots_, e.t});
    }
    ++s.events;
    observer(e);
  });
  s.ending = why == StopReason::NothingLeft && atRest() ? ShotEnd::Rest : ShotEnd::TimeLimit;
  if (s.ending == ShotEnd::TimeLimit) sim_.synchronize(s.start + limit);
  s.end = sim_.now();
  for (int i = 0; i < static_cast<int>(specs_.size()); ++i)
    if (sim_.ball(i).active) checkOnTable(i, s.end);
  s.keEnd = sim_.kineticEnergy();
  s.momentumEnd = sim_.momentum();
  if (s.ending == ShotEnd::TimeLimit) {
    for (int i = 0; i < static_cast<int>(specs_.size()); ++i) {
      if (!sim_.ball(i).active || sim_.ball(i).v.squaredNorm() == 0.0) continue;
      sim_.setVelocity(i, Vec2::Zero());
      observer(manual(PoolEventKind::Stop, i));
    }
  }
  ++shots_;
  return s;
}

}  // namespace st::pool

#include <starm/drive.hpp>

#include <algorithm>
#include <cmath>

#include <starm/monitor.hpp>
#include <starm/scenario.hpp>
#include <starm/ssm.hpp>

namespace st::arm {

double Ramp::at(double t) const {
  if (t <= t0 || rate == 0.0) return s0;
  // exactly at rest (or full speed) from the end of the ramp on, not a rounding residue
  const double target = rate < 0.0 ? 0.0 : 1.0;
  if (t >= t0 + (target - s0) / rate) return target;
  return std::clamp(s0 + rate * (t - t0), 0.0, 1.0);
}

double Ramp::integral(double a, double b) const {
  if (!(b > a)) return 0.0;
  double sum = 0.0;
  // before the ramp starts: constant s0
  if (a < t0) {
    const double e = std::min(b, t0);
    sum += s0 * (e - a);
    a = e;
    if (a >= b) return sum;
  }
  // the linear part until s hits 0 or 1, then constant
  const double target = rate < 0.0 ? 0.0 : 1.0;
  const double tEnd = rate == 0.0 ? b : t0 + (target - s0) / rate;
  if (a < tEnd) {
    const double e = std::min(b, tEnd);
    sum += 0.5 * (at(a) + at(e)) * (e - a);
    a = e;
  }
  if (a < b) sum += at(b) * (b - a);
  return sum;
}

double ArmDrive::advance(double t) {
  if (!started_) {
    started_ = true;
    last_ = t;
    tau_ = t;
    lag_ = 0.0;
    s_ = 1.0;
    return tau_;
  }
  if (t <= last_) return tau_;
  if (mode_ == DriveMode::Scaled) {
    advanceScaled(t);
  } else if (mode_ == DriveMode::Following) {
    // exact while following: tau = t - lag (no drift from summing cycle lengths)
    tau_ = t - lag_;
    s_ = 1.0;
  } else {
    tau_ += ramp_.integral(last_, t);
    s_ = ramp_.at(t);
    if (mode_ == DriveMode::Braking && s_ <= 0.0) mode_ = DriveMode::Stopped;
    if (mode_ == DriveMode::Resuming && s_ >= 1.0) {
      mode_ = DriveMode::Following;
      lag_ = t - tau_;
    }
  }
  last_ = t;
  return tau_;
}

double ArmDrive::brakingSpeed() const {
  if (mode_ == DriveMode::Resuming) return ramp_.at(last_ + cfg_.delay);
  return s_;
}

void ArmDrive::advanceScaled(double t) {
  // piecewise: s heads for the current target at the braking rate; targets change at their times
  const double rate = cfg_.stoppingTime > 0.0 ? 1.0 / cfg_.stoppingTime : std::numeric_limits<double>::infinity();
  double a = last_;
  while (a < t) {
    while (!targets_.empty() && targets_.front().first <= a) {
      target_ = targets_.front().second;
      targets_.pop_front();
    }
    const double b = targets_.empty() ? t : std::min(t, targets_.front().first);
    const double gap = target_ - s_;
    const double reach = std::abs(gap) / rate;  // time to get there
    if (reach >= b - a) {
      const double s1 = s_ + (gap > 0.0 ? 1.0 : -1.0) * rate * (b - a);
      tau_ += 0.5 * (s_ + s1) * (b - a);
      s_ = s1;
    } else {
      tau_ += 0.5 * (s_ + target_) * reach + target_ * (b - a - reach);
      s_ = target_;
    }
    a = b;
  }
  // back at full speed with nothing pending: following again, its lag as it stands
  if (s_ >= 1.0 && target_ >= 1.0 && targets_.empty()) {
    s_ = 1.0;
    mode_ = DriveMode::Following;
    lag_ = t - tau_;
  }
}

void ArmDrive::limit(double t, double factor) {
  factor = std::clamp(factor, 0.0, 1.0);
  if (mode_ == DriveMode::Braking || mode_ == DriveMode::Stopped) return;
  if (mode_ == DriveMode::Following && factor >= 1.0) return;
  if (mode_ == DriveMode::Resuming && factor >= ramp_.at(last_)) return;  // the resume ramp is below it
  if (mode_ != DriveMode::Scaled) {
    // from following (s = 1) or part way up a resume ramp, heading for full speed until the new factor is due
    s_ = mode_ == DriveMode::Following ? 1.0 : ramp_.at(last_);
    target_ = 1.0;
    targets_.clear();
    mode_ = DriveMode::Scaled;
  }
  const double last = targets_.empty() ? target_ : targets_.back().second;
  if (factor == last) return;
  targets_.emplace_back(std::max(t + cfg_.delay, last_), factor);
}

void ArmDrive::observe(double t, bool warned, bool stop, double rate, bool blocked) {
  if (warned) lastThreat_ = t;
  if (stop && (mode_ == DriveMode::Following || mode_ == DriveMode::Resuming || mode_ == DriveMode::Scaled)) {
    // braking starts `delay` after the STOP cycle, never before the next reading
    double stopping = cfg_.stoppingTime;
    if (cfg_.deceleration > 0.0) stopping = rate / cfg_.deceleration;
    const double start = std::max(t + cfg_.delay, last_);
    // scaled: the speed now, held until braking starts (the factors on their way are dropped)
    const double s0 = mode_ == DriveMode::Following ? 1.0 : mode_ == DriveMode::Scaled ? s_ : ramp_.at(start);
    targets_.clear();
    ramp_ = {start, s0, stopping > 0.0 ? -1.0 / stopping : -std::numeric_limits<double>::infinity()};
    if (!(stopping > 0.0)) ramp_ = {start, 0.0, 0.0};  // no braking time: at rest from the start
    mode_ = DriveMode::Braking;
    ++stops_;
    return;
  }
  if (mode_ == DriveMode::Stopped && cfg_.resumes() && !warned && !blocked && t - lastThreat_ >= cfg_.resumeAfter) {
    double ramp = cfg_.stoppingTime;
    if (cfg_.deceleration > 0.0) ramp = std::max(rate, 1e-9) / cfg_.deceleration;
    const double start = std::max(t, last_);
    ramp_ = ramp > 0.0 ? Ramp{start, 0.0, 1.0 / ramp} : Ramp{start, 1.0, 0.0};
    mode_ = DriveMode::Resuming;
    ++resumes_;
  }
}

ClosedLoopSensor::ClosedLoopSensor(std::unique_ptr<SensorSource> nominal, std::vector<ArmModel> models, BrakeConfig cfg)
    : nominal_(std::move(nominal)), models_(std::move(models)) {
  arms_.resize(models_.size());
  for (ArmFeed& f : arms_) f.drive = ArmDrive(cfg);
}

void ClosedLoopSensor::sampleAt(ArmFeed& f, double tau, Reading& r) const {
  // drop samples wholly behind tau (keep the one at or before it)
  while (f.head + 1 < f.buffer.size() && f.buffer[f.head + 1].t <= tau) ++f.head;
  if (f.head > 1024 && f.head * 2 > f.buffer.size()) {
    f.buffer.erase(f.buffer.begin(), f.buffer.begin() + static_cast<std::ptrdiff_t>(f.head));
    f.head = 0;
  }
  const Sample& a = f.buffer[f.head];
  if (f.head + 1 >= f.buffer.size() || tau <= a.t) {
    r.q = a.q;
    r.qdot = a.qdot;
    return;
  }
  const Sample& b = f.buffer[f.head + 1];
  const double u = (tau - a.t) / (b.t - a.t);
  r.q.resize(a.q.size());
  r.qdot.resize(a.q.size());
  for (std::size_t k = 0; k < a.q.size(); ++k) {
    r.q[k] = a.q[k] + u * (b.q[k] - a.q[k]);
    r.qdot[k] = a.qdot[k] + u * (b.qdot[k] - a.qdot[k]);
  }
}

bool ClosedLoopSensor::next(Reading& r) {
  Reading n;
  if (!nominal_->next(n)) return false;
  if (n.arm < 0 || n.arm >= static_cast<int>(arms_.size())) throw InputError(n.where + ": unknown arm");
  if (!models_[n.arm].joints.empty()) validateReading(models_[n.arm], n);
  ArmFeed& f = arms_[n.arm];
  if (!f.buffer.empty() && n.t < f.buffer.back().t)
    throw InputError(n.where + ": time " + std::to_string(n.t) + " s goes backwards");
  // a stopped arm that never resumes needs no future samples
  if (!(f.drive.heldForGood() && !f.buffer.empty())) f.buffer.push_back({n.t, n.q, n.qdot});
  f.seen = true;
  const double tau = f.drive.advance(n.t);
  r.t = n.t;
  r.arm = n.arm;
  r.where = n.where;
  sampleAt(f, tau, r);
  const double s = f.drive.speed();
  for (double& v : r.qdot) v *= s;
  return true;
}

void ClosedLoopSensor::observe(const Monitor& m, double t, const SeparationMonitor* ssm) {
  for (int a = 0; a < static_cast<int>(arms_.size()); ++a) {
    const SsmVerdict* v = ssm ? &ssm->verdict(a) : nullptr;
    const bool ssmStop = v && v->stop;
    if (v && ssm->config().response != SsmResponse::Stop)
      // graded: the person's STOP stops the arm and holds it while the factor is 0, no longer
      observeArm(a, t, m.warned(a), m.stopped(a) || ssmStop, ssmStop || v->factor <= 0.0);
    else
      observeArm(a, t, m.warned(a) || ssmStop, m.stopped(a) || ssmStop);
    if (v) limitArm(a, t, v->factor);
  }
}

void ClosedLoopSensor::observeArm(int a, double t, bool warned, bool stop, bool blocked) {
  ArmFeed& f = arms_[a];
  if (!f.seen) return;
  double rate = 0.0;
  if (f.head < f.buffer.size())
    for (double v : f.buffer[f.head].qdot) rate = std::max(rate, std::abs(v));
  f.drive.observe(t, warned, stop, rate, blocked);
}

void ClosedLoopSensor::limitArm(int a, double t, double factor) {
  ArmFeed& f = arms_[a];
  if (f.seen) f.drive.limit(t, factor);
}

std::unique_ptr<ClosedLoopSensor> makeClosedLoopSensor(const Scenario& s) {
  std::vector<ArmModel> models;
  for (const ArmInstance& a : s.arms) models.push_back(a.model);
  return std::make_unique<ClosedLoopSensor>(makeSensor(s), std::move(models), s.braking);
}

}  // namespace st::arm

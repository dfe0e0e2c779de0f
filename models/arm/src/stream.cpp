#include <starm/stream.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <limits>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <thread>

#include <starm/scenario.hpp>
#include <stio/format.hpp>
#include <stnet/client.hpp>

namespace st::arm {

namespace {

using Clock = std::chrono::steady_clock;

std::string num(double x) { return io::number(x, 9); }

// The next message that is not an ERROR; an ERROR becomes an exception with its text. While a
// cycle's verdict is awaited, an ERROR is the service refusing that cycle's readings (a joint
// outside its limits, a time it will not take): an InputError named by the cycle's trace line.
proto::Message expect(net::Client& c, std::chrono::milliseconds timeout, const char* what,
                      const std::string* cycleWhere = nullptr) {
  const auto frame = c.receive(timeout);
  if (!frame) throw std::runtime_error(std::string(c.closed() ? "the service closed the connection" : "no answer") +
                                       " waiting for " + what);
  proto::Decoded d = proto::decode(*frame);
  if (!d.ok) throw std::runtime_error("bad message from the service: " + d.error);
  if (const auto* e = std::get_if<proto::Error>(&d.message)) {
    if (cycleWhere) throw InputError(*cycleWhere + ": the service refused this reading: " + e->message);
    throw std::runtime_error("service: " + e->message);
  }
  return std::move(d.message);
}

// Connects and greets: HELLO answered by WELCOME (the service's arms and obstacles).
proto::Welcome greet(net::Client& client, const std::string& host, std::uint16_t port, const std::string& token,
                     std::chrono::milliseconds timeout) {
  client.connect(host, port);
  client.send(proto::encode(proto::Hello{proto::kVersion, token}));
  proto::Message m = expect(client, timeout, "WELCOME");
  auto* w = std::get_if<proto::Welcome>(&m);
  if (!w) throw std::runtime_error("the service did not answer HELLO with WELCOME");
  return std::move(*w);
}

// stream_verdicts.csv in cfg.outDir (none without one)
std::optional<io::CsvRowWriter> openLog(const StreamConfig& cfg, const std::vector<std::string>& armNames) {
  std::optional<io::CsvRowWriter> log;
  if (cfg.outDir.empty()) return log;
  std::filesystem::create_directories(cfg.outDir);
  std::string header = "t_s,seq,rtt_us";
  for (const std::string& n : armNames) header += ',' + io::csvField(n + "_level") + ',' + io::csvField(n + "_speed");
  log.emplace(std::filesystem::path(cfg.outDir) / "stream_verdicts.csv", header + ",distance_m,ttc_s");
  return log;
}

// One cycle's message: every reading of the trace at r's time (r and have then hold the next
// one). Returns where the cycle is in the trace: its first line, and its count when several.
std::string gatherCycle(SensorSource& src, Reading& r, bool& have, proto::Readings& msg) {
  const double t = r.t;
  msg.t = t;
  msg.arms.clear();
  std::string cycleWhere = r.where;
  int cycleLines = 0;
  while (have && r.t == t) {
    ++cycleLines;
    // named by its trace line here; the service would name only its message
    for (std::size_t k = 0; k < r.q.size(); ++k) {
      const std::string joint = "joint " + std::to_string(k + 1);
      if (!std::isfinite(r.q[k])) throw InputError(r.where + ": " + joint + " angle is not a finite number");
      if (!std::isfinite(r.qdot[k])) throw InputError(r.where + ": " + joint + " rate is not a finite number");
    }
    msg.arms.push_back({static_cast<std::uint16_t>(r.arm), r.q, r.qdot});
    have = src.next(r);
  }
  if (cycleLines > 1) cycleWhere += " (the first of the " + std::to_string(cycleLines) + " lines at t = " + num(t) + " s)";
  return cycleWhere;
}

// The verdict of cycle seq (ack = seq), held in got; older ones that arrive late are skipped.
// Null when none came within the timeout.
const proto::Verdict* awaitVerdict(net::Client& client, const StreamConfig& cfg, std::uint32_t seq,
                                   Clock::time_point sent, const std::string& cycleWhere, proto::Message& got) {
  while (true) {
    const auto left = cfg.verdictTimeout - std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - sent);
    if (left.count() <= 0) return nullptr;
    got = expect(client, left, "a VERDICT", &cycleWhere);
    const auto* v = std::get_if<proto::Verdict>(&got);
    if (v && v->ack >= seq) return v;
  }
}

// A verdict's STOPs into the result and, in the closed loop, into the arms' drives.
void observe(const proto::Verdict& v, double t, int arms, ClosedLoopSensor* loop, StreamResult& res) {
  bool anyStop = false;
  for (int a = 0; a < arms && a < static_cast<int>(v.arms.size()); ++a) {
    const bool stop = v.arms[a].level == proto::Level::Stop;
    anyStop = anyStop || stop;
    if (stop && std::isnan(res.firstStop[a])) res.firstStop[a] = t;
    if (loop) {
      loop->observeArm(a, t, stop, stop);
      // version 3: the speed factor of speed and separation monitoring (1 without persons)
      loop->limitArm(a, t, v.arms[a].factor);
    }
  }
  res.stopCycles += anyStop ? 1 : 0;
  res.minDistance = std::min(res.minDistance, v.nearest.distance);
}

// stream_verdicts.csv's row of a verdict
std::string logRow(const proto::Verdict& v, double t, std::uint32_t seq, double rtt, int arms, const ClosedLoopSensor* loop) {
  std::ostringstream line;
  line << num(t) << ',' << seq << ',' << num(rtt);
  for (int a = 0; a < arms; ++a)
    line << ',' << proto::toString(a < static_cast<int>(v.arms.size()) ? v.arms[a].level : proto::Level::Ok) << ','
         << num(loop ? loop->drive(a).speed() : 1.0);
  line << ',' << num(v.nearest.distance) << ',' << num(v.nearest.ttc);
  return line.str();
}

}  // namespace

std::vector<std::string> resetLatches(const std::string& host, std::uint16_t port, const std::string& token,
                                      const std::vector<std::string>& arms) {
  net::Client client;
  const proto::Welcome welcome = greet(client, host, port, token, std::chrono::milliseconds(2000));
  const proto::Welcome* w = &welcome;
  proto::Reset reset;
  std::vector<std::string> named;
  for (std::size_t a = 0; a < w->armNames.size(); ++a)
    if (arms.empty() || std::find(arms.begin(), arms.end(), w->armNames[a]) != arms.end()) {
      reset.arms.push_back(static_cast<std::uint16_t>(a));
      named.push_back(w->armNames[a]);
    }
  for (const std::string& a : arms)
    if (std::find(named.begin(), named.end(), a) == named.end()) throw std::runtime_error("no arm '" + a + "' in the service's scenario");
  client.send(proto::encode(reset));
  // a SUBSCRIBE and the next VERDICT would wait on the sensors; a refusal comes back at once
  if (const auto f = client.receive(std::chrono::milliseconds(200))) {
    const proto::Decoded d = proto::decode(*f);
    if (d.ok && std::holds_alternative<proto::Error>(d.message))
      throw std::runtime_error("service: " + std::get<proto::Error>(d.message).message);
  }
  return named;
}

void runStream(const StreamConfig& cfg, StreamResult& res) {
  net::Client client;
  const proto::Welcome w = greet(client, cfg.host, cfg.port, cfg.token, cfg.verdictTimeout);
  client.send(proto::encode(proto::Subscribe{proto::Subscribe::kOwnOnly}));

  const int arms = static_cast<int>(w.armNames.size());
  res.armNames = w.armNames;
  res.firstStop.assign(arms, std::numeric_limits<double>::quiet_NaN());
  res.finalSpeed.assign(arms, 1.0);
  res.minDistance = std::numeric_limits<double>::infinity();
  std::vector<int> dofs(w.armDofs.begin(), w.armDofs.end());
  auto csv = std::make_unique<CsvSensor>(cfg.trace, w.armNames, dofs);
  std::unique_ptr<ClosedLoopSensor> loop;
  SensorSource* src = csv.get();
  if (cfg.closedLoop) {
    // the client knows the joint counts only; the service checks the readings against the models
    loop = std::make_unique<ClosedLoopSensor>(std::move(csv), std::vector<ArmModel>(arms), cfg.braking);
    src = loop.get();
  }
  std::optional<io::CsvRowWriter> log = openLog(cfg, w.armNames);

  proto::Readings msg;
  Reading r;
  bool have = src->next(r);
  const auto wallStart = Clock::now();
  const double t0 = have ? r.t : 0.0;
  while (have) {
    if (cfg.stopRequested && cfg.stopRequested()) {
      res.interrupted = true;
      break;
    }
    // one cycle: every reading of the trace at this time, in one message, and its verdict
    const double t = r.t;
    const std::string cycleWhere = gatherCycle(*src, r, have, msg);
    ++msg.seq;
    if (cfg.rate > 0.0)
      std::this_thread::sleep_until(wallStart + std::chrono::duration_cast<Clock::duration>(
                                                    std::chrono::duration<double>((t - t0) / cfg.rate)));
    const auto sent = Clock::now();
    client.send(proto::encode(msg));
    ++res.cycles;
    proto::Message got;
    const proto::Verdict* v = awaitVerdict(client, cfg, msg.seq, sent, cycleWhere, got);
    if (!v) {
      ++res.timeouts;
      continue;
    }
    const double rtt = std::chrono::duration<double, std::micro>(Clock::now() - sent).count();
    res.rttUs.push_back(rtt);
    ++res.verdicts;
    observe(*v, t, arms, loop.get(), res);
    if (log) log->row(logRow(*v, t, msg.seq, rtt, arms, loop.get()));
  }
  if (loop)
    for (int a = 0; a < arms; ++a) res.finalSpeed[a] = loop->drive(a).speed();
  if (log) log->flush();
  if (res.cycles == 0 && !res.interrupted) throw InputError(cfg.trace + ": holds no readings (an empty sensor trace)");
  client.close();
}

RecordingSensor::RecordingSensor(SensorSource& inner, const std::string& path, std::vector<std::string> armNames)
    : inner_(inner), out_(path, "t,arm,q...,qdot..."), names_(std::move(armNames)) {}

bool RecordingSensor::next(Reading& r) {
  if (!inner_.next(r)) {
    out_.flush();
    return false;
  }
  // the CsvSensor format: names as they are (it splits on commas), every number read back exactly
  line_ = io::number(r.t, 17);
  line_ += ',';
  line_ += names_[r.arm];
  for (double v : r.q) (line_ += ',') += io::number(v, 17);
  for (double v : r.qdot) (line_ += ',') += io::number(v, 17);
  out_.row(line_);
  return true;
}

}  // namespace st::arm

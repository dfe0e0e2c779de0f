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

}  // namespace

std::vector<std::string> resetLatches(const std::string& host, std::uint16_t port, const std::string& token,
                                      const std::vector<std::string>& arms) {
  net::Client client;
  client.connect(host, port);
  client.send(proto::encode(proto::Hello{proto::kVersion, token}));
  const proto::Message m = expect(client, std::chrono::milliseconds(2000), "WELCOME");
  const auto* w = std::get_if<proto::Welcome>(&m);
  if (!w) throw std::runtime_error("the service did not answer HELLO with WELCOME");
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
  client.connect(cfg.host, cfg.port);
  client.send(proto::encode(proto::Hello{proto::kVersion, cfg.token}));
  const proto::Message m = expect(client, cfg.verdictTimeout, "WELCOME");
  const auto* w = std::get_if<proto::Welcome>(&m);
  if (!w) throw std::runtime_error("the service did not answer HELLO with WELCOME");
  client.send(proto::encode(proto::Subscribe{proto::Subscribe::kOwnOnly}));

  const int arms = static_cast<int>(w->armNames.size());
  res.armNames = w->armNames;
  res.firstStop.assign(arms, std::numeric_limits<double>::quiet_NaN());
  res.finalSpeed.assign(arms, 1.0);
  res.minDistance = std::numeric_limits<double>::infinity();
  std::vector<int> dofs(w->armDofs.begin(), w->armDofs.end());
  auto csv = std::make_unique<CsvSensor>(cfg.trace, w->armNames, dofs);
  std::unique_ptr<ClosedLoopSensor> loop;
  SensorSource* src = csv.get();
  if (cfg.closedLoop) {
    // the client knows the joint counts only; the service checks the readings against the models
    loop = std::make_unique<ClosedLoopSensor>(std::move(csv), std::vector<ArmModel>(arms), cfg.braking);
    src = loop.get();
  }
  std::optional<io::CsvRowWriter> log;
  if (!cfg.outDir.empty()) {
    std::filesystem::create_directories(cfg.outDir);
    std::string header = "t_s,seq,rtt_us";
    for (const std::string& n : w->armNames) header += ',' + io::csvField(n + "_level") + ',' + io::csvField(n + "_speed");
    log.emplace(std::filesystem::path(cfg.outDir) / "stream_verdicts.csv", header + ",distance_m,ttc_s");
  }
  std::ostringstream line;

  proto::Readings msg;
  Reading r;
  bool have = src->next(r);
  const auto wallStart = Clock::now();
  const double t0 = have ? r.t : 0.0;
  std::string out;
  while (have) {
    if (cfg.stopRequested && cfg.stopRequested()) {
      res.interrupted = true;
      break;
    }
    // one cycle: every reading of the trace at this time, in one message
    const double t = r.t;
    msg.t = t;
    msg.arms.clear();
    std::string cycleWhere = r.where;  // the cycle's first trace line; its count when several
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
      have = src->next(r);
    }
    if (cycleLines > 1) cycleWhere += " (the first of the " + std::to_string(cycleLines) + " lines at t = " + num(t) + " s)";
    ++msg.seq;
    if (cfg.rate > 0.0)
      std::this_thread::sleep_until(wallStart + std::chrono::duration_cast<Clock::duration>(
                                                    std::chrono::duration<double>((t - t0) / cfg.rate)));
    const auto sent = Clock::now();
    client.send(proto::encode(msg));
    ++res.cycles;
    // the verdict of this cycle (ack = seq); older ones that arrive late are skipped
    const proto::Verdict* v = nullptr;
    proto::Message got;
    while (true) {
      const auto left = cfg.verdictTimeout - std::chrono::duration_cast<std::chrono::milliseconds>(Clock::now() - sent);
      if (left.count() <= 0) break;
      got = expect(client, left, "a VERDICT", &cycleWhere);
      v = std::get_if<proto::Verdict>(&got);
      if (v && v->ack >= msg.seq) break;
      v = nullptr;
    }
    if (!v) {
      ++res.timeouts;
      continue;
    }
    const double rtt = std::chrono::duration<double, std::micro>(Clock::now() - sent).count();
    res.rttUs.push_back(rtt);
    ++res.verdicts;
    bool anyStop = false;
    for (int a = 0; a < arms && a < static_cast<int>(v->arms.size()); ++a) {
      const bool stop = v->arms[a].level == proto::Level::Stop;
      anyStop = anyStop || stop;
      if (stop && std::isnan(res.firstStop[a])) res.firstStop[a] = t;
      if (loop) {
        loop->observeArm(a, t, stop, stop);
        // version 3: the speed factor of speed and separation monitoring (1 without persons)
        loop->limitArm(a, t, v->arms[a].factor);
      }
    }
    res.stopCycles += anyStop ? 1 : 0;
    res.minDistance = std::min(res.minDistance, v->nearest.distance);
    if (log) {
      line.str("");
      line << num(t) << ',' << msg.seq << ',' << num(rtt);
      for (int a = 0; a < arms; ++a)
        line << ',' << proto::toString(a < static_cast<int>(v->arms.size()) ? v->arms[a].level : proto::Level::Ok) << ','
             << num(loop ? loop->drive(a).speed() : 1.0);
      line << ',' << num(v->nearest.distance) << ',' << num(v->nearest.ttc);
      log->row(line.str());
    }
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

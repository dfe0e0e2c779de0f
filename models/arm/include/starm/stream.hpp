#pragma once
// The arm service's sensor client (`stsim arm stream`): replays a recorded sensor trace
// (`t, arm, q1..qn, qdot1..qdotn`, the CsvSensor format) to a service at real time or `rate`
// times faster, one READINGS message per trace time, waits for that cycle's verdict and, in
// closed loop, applies STOP to its own replay (starm/drive.hpp): closed loop through the
// network. Records every verdict and its round-trip time.
#include <chrono>
#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include <starm/drive.hpp>
#include <starm/protocol.hpp>
#include <stio/output.hpp>

namespace st::arm {

struct StreamConfig {
  std::string host = "127.0.0.1";
  std::uint16_t port = 0;
  std::string token;
  std::string trace;           // CSV sensor trace
  double rate = 1.0;           // replay speed; 0: as fast as the verdicts come back
  bool closedLoop = true;
  BrakeConfig braking;         // how this client's arms brake on STOP
  std::string outDir;          // stream_verdicts.csv ("" : none)
  std::chrono::milliseconds verdictTimeout{2000};
  std::function<bool()> stopRequested;  // asked before each cycle; true ends the replay there
};

struct StreamResult {
  std::uint64_t cycles = 0, verdicts = 0, timeouts = 0, stopCycles = 0;
  std::vector<double> rttUs;       // per answered cycle
  std::vector<double> firstStop;   // per arm, trace time of the first STOP verdict (NaN: none)
  std::vector<double> finalSpeed;  // per arm, program speed at the end (0: stopped)
  std::vector<std::string> armNames;
  double minDistance = 0.0;        // smallest nearest-pair distance the verdicts reported
  bool interrupted = false;        // stopRequested ended the replay before the trace did
};

// Throws std::runtime_error on a refused connection or an ERROR from the service (its message),
// InputError on a bad trace line. `result` holds what was measured up to then.
void runStream(const StreamConfig& cfg, StreamResult& result);

// `stsim arm reset`: asks the service at host:port to release the latched STOPs of the named
// arms (all when empty), held since their sensors fell silent. Returns the arms named; throws
// std::runtime_error for an unknown arm name or a service that refuses.
std::vector<std::string> resetLatches(const std::string& host, std::uint16_t port, const std::string& token,
                                      const std::vector<std::string>& arms);

// A sensor source that writes every reading it passes on as a CSV trace line.
class RecordingSensor final : public SensorSource {
 public:
  RecordingSensor(SensorSource& inner, const std::string& path, std::vector<std::string> armNames);
  bool next(Reading& r) override;

 private:
  SensorSource& inner_;
  io::CsvRowWriter out_;
  std::vector<std::string> names_;
  std::string line_;  // reused
};

}  // namespace st::arm

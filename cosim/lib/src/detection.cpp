#include <stcosim/detection.hpp>

#include <signal.h>

#include <stdexcept>
#include <utility>

namespace st::cosim {

bool detectionCanOverlap(const PluginConfig& config) {
  // brake acts in SUMO on the tick's alerts and must do so before its next step; colour only
  // paints, so it may reach SUMO a step late; incidents need only the states and stay on SUMO's
  // thread in prepare()
  return config.actions.action != Action::Brake;
}

DetectionStage::DetectionStage(HighwayPlugin& plugin, bool overlap, std::function<void()> collect)
    : plugin_(plugin), collect_(std::move(collect)) {
  if (!overlap) return;
  if (!detectionCanOverlap(plugin.config()))
    throw std::invalid_argument(std::string("detection cannot overlap SUMO's step with action ") +
                                toString(plugin.config().actions.action) + ": it must reach SUMO before the next step");
  // the worker blocks every signal, so Ctrl-C lands on SUMO's thread and wakes its blocking waits
  sigset_t all, old;
  sigfillset(&all);
  pthread_sigmask(SIG_BLOCK, &all, &old);
  worker_ = std::thread([this] { work(); });
  pthread_sigmask(SIG_SETMASK, &old, nullptr);
}

DetectionStage::~DetectionStage() {
  if (!worker_.joinable()) return;
  {
    std::lock_guard lock(mutex_);
    quit_ = true;
  }
  wake_.notify_one();
  worker_.join();  // a running detection finishes first
}

void DetectionStage::work() {
  std::unique_lock lock(mutex_);
  for (;;) {
    wake_.wait(lock, [this] { return job_ || quit_; });
    if (!job_) return;
    lock.unlock();
    std::exception_ptr error;
    try {
      plugin_.detect();
    } catch (...) {
      error = std::current_exception();
    }
    lock.lock();
    error_ = error;
    job_ = false;
    done_.notify_one();
  }
}

void DetectionStage::start() {
  {
    std::lock_guard lock(mutex_);
    job_ = true;
  }
  pending_ = true;
  wake_.notify_one();
}

void DetectionStage::wait() {
  if (!pending_) return;
  std::exception_ptr error;
  {
    std::unique_lock lock(mutex_);
    done_.wait(lock, [this] { return !job_; });
    error = std::exchange(error_, nullptr);
  }
  pending_ = false;
  // a failed detection is not collected, as in line (the exception leaves update() before)
  if (error) std::rethrow_exception(error);
  // collected before the colours go to SUMO, so a connection lost on them loses no warning
  collect_();
  plugin_.act();
}

void DetectionStage::afterStep() {
  if (!overlapped()) {
    plugin_.update();
    collect_();
    return;
  }
  wait();
  plugin_.prepare();
  start();
}

void DetectionStage::drain() { wait(); }

}  // namespace st::cosim

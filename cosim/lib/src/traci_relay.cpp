#include "traci_relay.hpp"

#include <arpa/inet.h>
#include <fcntl.h>
#include <netdb.h>
#include <netinet/in.h>
#include <netinet/tcp.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <algorithm>
#include <cerrno>
#include <cstdio>
#include <cstring>

#include <stcosim/backend.hpp>

namespace st::cosim::detail {
namespace {

void noDelay(int fd) {
  int one = 1;
  ::setsockopt(fd, IPPROTO_TCP, TCP_NODELAY, &one, sizeof one);
}

bool sendAll(int fd, const unsigned char* p, std::size_t n) {
  while (n > 0) {
    const ssize_t k = ::send(fd, p, n, MSG_NOSIGNAL);
    if (k < 0 && errno == EINTR) continue;
    if (k <= 0) return false;
    p += k;
    n -= static_cast<std::size_t>(k);
  }
  return true;
}

int connectTo(const std::string& host, int port, std::string& error) {
  addrinfo hints{};
  hints.ai_family = AF_UNSPEC;
  hints.ai_socktype = SOCK_STREAM;
  addrinfo* found = nullptr;
  const int rc = ::getaddrinfo(host.c_str(), std::to_string(port).c_str(), &hints, &found);
  if (rc != 0) {
    error = std::string("cannot resolve '") + host + "': " + ::gai_strerror(rc);
    return -1;
  }
  int fd = -1;
  for (addrinfo* a = found; a != nullptr && fd < 0; a = a->ai_next) {
    fd = ::socket(a->ai_family, a->ai_socktype | SOCK_CLOEXEC, a->ai_protocol);
    if (fd < 0) continue;
    if (::connect(fd, a->ai_addr, a->ai_addrlen) != 0) {
      error = std::strerror(errno);
      ::close(fd);
      fd = -1;
    }
  }
  ::freeaddrinfo(found);
  return fd;
}

}  // namespace

TraciRelay::TraciRelay(const std::string& host, int port, int attempts, double firstReplySeconds, double silenceSeconds)
    : firstReplySeconds_(firstReplySeconds), silenceSeconds_(silenceSeconds) {
  std::string error;
  for (int i = 0; i < std::max(1, attempts) && serverFd_ < 0; ++i) {
    if (i > 0) std::this_thread::sleep_for(std::chrono::seconds(1));
    serverFd_ = connectTo(host, port, error);
  }
  if (serverFd_ < 0) throw SumoError(error);
  noDelay(serverFd_);

  listenFd_ = ::socket(AF_INET, SOCK_STREAM | SOCK_CLOEXEC, 0);
  sockaddr_in addr{};
  addr.sin_family = AF_INET;
  addr.sin_addr.s_addr = htonl(INADDR_LOOPBACK);
  socklen_t len = sizeof addr;
  if (listenFd_ < 0 || ::bind(listenFd_, reinterpret_cast<sockaddr*>(&addr), sizeof addr) != 0 ||
      ::listen(listenFd_, 1) != 0 || ::getsockname(listenFd_, reinterpret_cast<sockaddr*>(&addr), &len) != 0 ||
      ::pipe2(wakeFd_, O_CLOEXEC) != 0) {
    const std::string why = std::strerror(errno);
    for (int fd : {serverFd_, listenFd_, wakeFd_[0], wakeFd_[1]})
      if (fd >= 0) ::close(fd);
    throw SumoError("cannot open a loopback socket for TraCI: " + why);
  }
  localPort_ = ntohs(addr.sin_port);
  thread_ = std::thread([this] { run(); });
}

TraciRelay::~TraciRelay() {
  const char stop = 1;
  [[maybe_unused]] const ssize_t k = ::write(wakeFd_[1], &stop, 1);
  thread_.join();
  for (int fd : {clientFd_, serverFd_, listenFd_, wakeFd_[0], wakeFd_[1]})
    if (fd >= 0) ::close(fd);
}

std::string TraciRelay::failure() const {
  std::lock_guard<std::mutex> lock(mutex_);
  return failure_;
}

void TraciRelay::closeWithin(double seconds) {
  closeDeadline_.store(std::chrono::duration<double>(Clock::now().time_since_epoch()).count() + seconds);
}

void TraciRelay::fail(const std::string& why) {
  std::lock_guard<std::mutex> lock(mutex_);
  if (failure_.empty()) failure_ = why;
}

// Passes the client's bytes on and notes its requests.
bool TraciRelay::forwardRequests() {
  unsigned char buf[65536];
  const ssize_t n = ::recv(clientFd_, buf, sizeof buf, 0);
  if (n < 0 && (errno == EINTR || errno == EAGAIN)) return true;
  if (n <= 0) return false;  // libtraci closed its side: we are done
  if (!sendAll(serverFd_, buf, static_cast<std::size_t>(n))) return false;  // the server is gone: libtraci learns on recv
  framing_.request(buf, static_cast<std::size_t>(n), Clock::now());
  return true;
}

// Passes on every complete, well-framed reply; returns false (after fail()) on a malformed one.
bool TraciRelay::passReplies() {
  std::string failure;
  const std::size_t whole = framing_.replies(reply_.data(), reply_.size(), failure);
  if (whole > 0) {
    if (!sendAll(clientFd_, reply_.data(), whole)) return false;
    reply_.erase(reply_.begin(), reply_.begin() + static_cast<std::ptrdiff_t>(whole));
    replyBegan_ = Clock::now();  // the next reply's first bytes, if any, arrived now
  }
  if (!failure.empty()) {
    fail(failure);
    return false;
  }
  return true;
}

void TraciRelay::run() {
  unsigned char buf[65536];
  for (;;) {
    pollfd fds[3];
    fds[0] = {wakeFd_[0], POLLIN, 0};
    fds[1] = {clientFd_ >= 0 ? clientFd_ : listenFd_, POLLIN, 0};
    fds[2] = {serverFd_, POLLIN, 0};
    const int ready = ::poll(fds, 3, 100);
    if (ready < 0 && errno != EINTR) break;
    if (fds[0].revents) break;  // destructor
    const auto now = Clock::now();
    if (ready > 0 && fds[1].revents) {
      if (clientFd_ < 0) {
        clientFd_ = ::accept4(listenFd_, nullptr, nullptr, SOCK_CLOEXEC);
        if (clientFd_ >= 0) {
          noDelay(clientFd_);
          ::close(listenFd_);
          listenFd_ = -1;
        }
      } else if (!forwardRequests()) {
        break;
      }
    }
    if (ready > 0 && fds[2].revents) {
      const ssize_t n = ::recv(serverFd_, buf, sizeof buf, 0);
      if (n <= 0 && !(n < 0 && (errno == EINTR || errno == EAGAIN))) {
        if (!reply_.empty())
          fail("the server closed the connection in the middle of a reply (" + std::to_string(reply_.size()) +
               " bytes of it received)");
        break;  // closing our side tells libtraci
      }
      if (n > 0) {
        if (reply_.empty()) replyBegan_ = now;
        reply_.insert(reply_.end(), buf, buf + n);
        if (!passReplies()) break;
      }
    }
    if (!reply_.empty() && now - replyBegan_ > std::chrono::duration<double>(kStallSeconds)) {
      fail("a TraCI reply stopped after " + std::to_string(reply_.size()) + " bytes for " +
           std::to_string(static_cast<int>(kStallSeconds)) + " s");
      break;
    }
    if (reply_.empty() && !framing_.pending().empty()) {
      const double limit = framing_.answered() ? silenceSeconds_ : firstReplySeconds_;
      if (now - framing_.pending().front().sent > std::chrono::duration<double>(limit)) {
        char msg[200];
        std::snprintf(msg, sizeof msg,
                      framing_.answered() ? "no reply for %.0f s (is SUMO stopped? with --num-clients, is every client stepping?)"
                                : "no TraCI answer within %.0f s (not a SUMO started with --remote-port?)",
                      limit);
        fail(msg);
        break;
      }
    }
    const double deadline = closeDeadline_.load();
    if (deadline >= 0.0 && !framing_.pending().empty() &&
        std::chrono::duration<double>(now.time_since_epoch()).count() > deadline) {
      fail("no reply to the closing request");
      break;
    }
  }
  // end both connections: libtraci's next (or current) receive fails with "peer shutdown"; a
  // connection still waiting to be accepted is reset when the listener closes
  if (listenFd_ >= 0) {
    ::close(listenFd_);
    listenFd_ = -1;
  }
  if (clientFd_ >= 0) ::shutdown(clientFd_, SHUT_RDWR);
  if (serverFd_ >= 0) ::shutdown(serverFd_, SHUT_RDWR);
}

}  // namespace st::cosim::detail

#include "listen.hpp"

#include <csignal>
#include <stdexcept>

namespace st::net::detail {

namespace asio = boost::asio;
using tcp = asio::ip::tcp;

void listen(tcp::acceptor& acceptor, const std::string& address, unsigned short port) {
  boost::system::error_code ec;
  const auto addr = asio::ip::make_address(address, ec);
  if (ec) throw std::runtime_error(address + ": not an IP address");
  const tcp::endpoint ep(addr, port);
  acceptor.open(ep.protocol(), ec);
  if (!ec) acceptor.set_option(tcp::acceptor::reuse_address(true), ec);
  if (!ec) acceptor.bind(ep, ec);
  if (!ec) acceptor.listen(asio::socket_base::max_listen_connections, ec);
  if (ec) throw std::runtime_error(address + ":" + std::to_string(port) + ": cannot listen: " + ec.message());
}

void watchStopSignals(asio::signal_set& signals, std::function<void(int)> onStop) {
  signals.add(SIGINT);
  signals.add(SIGTERM);
  signals.add(SIGHUP);
  signals.async_wait([onStop = std::move(onStop)](const boost::system::error_code& e, int signo) {
    if (!e) onStop(signo);
  });
}

}  // namespace st::net::detail

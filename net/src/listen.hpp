#pragma once
// What the framed Server and the WebServer share: listening on an address (loopback unless told
// otherwise, port 0 picks one) and stopping on the signals every stsim command stops on.
#include <functional>
#include <string>

#include <boost/asio/ip/tcp.hpp>
#include <boost/asio/signal_set.hpp>

namespace st::net::detail {

// Opens, binds and listens; throws std::runtime_error naming the address on failure.
void listen(boost::asio::ip::tcp::acceptor& acceptor, const std::string& address, unsigned short port);

// SIGINT / SIGTERM / SIGHUP (app/src/stop_signals.hpp) call onStop(signal) once.
void watchStopSignals(boost::asio::signal_set& signals, std::function<void(int)> onStop);

}  // namespace st::net::detail

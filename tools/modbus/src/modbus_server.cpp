#include "dynweigh/modbus/modbus_server.hpp"

#include <fcntl.h>
#include <modbus/modbus.h>
#include <poll.h>
#include <sys/socket.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

namespace dynweigh::modbus {

struct ModbusServer::Context {
  modbus_t* modbus = nullptr;
  modbus_mapping_t* mapping = nullptr;
  int listen_socket = -1;
  bool tcp = true;
  ~Context() {
    if (listen_socket >= 0) ::close(listen_socket);
    if (mapping) modbus_mapping_free(mapping);
    if (modbus) {
      if (!tcp) modbus_close(modbus);
      modbus_free(modbus);
    }
  }
};

ModbusServer::ModbusServer(const Endpoint& endpoint, PlcMailbox& mailbox)
    : mailbox_(mailbox), context_(std::make_unique<Context>()) {
  Context& c = *context_;
  c.tcp = endpoint.kind == Endpoint::Kind::tcp;
  const std::string where = "--modbus " + endpoint.text;
  if (c.tcp) {
    c.modbus = modbus_new_tcp_pi(endpoint.host.c_str(), endpoint.port.c_str());
    if (!c.modbus) throw std::runtime_error(where + ": " + modbus_strerror(errno));
    c.listen_socket = modbus_tcp_pi_listen(c.modbus, 64);
    if (c.listen_socket < 0) throw std::runtime_error(where + ": cannot listen: " + modbus_strerror(errno));
  } else {
    c.modbus = modbus_new_rtu(endpoint.device.c_str(), endpoint.baud, endpoint.parity, 8, 1);
    if (!c.modbus) throw std::runtime_error(where + ": " + modbus_strerror(errno));
    modbus_set_slave(c.modbus, endpoint.unit_id);
    if (modbus_connect(c.modbus) != 0) {
      throw std::runtime_error(where + ": cannot open " + endpoint.device + ": " + modbus_strerror(errno));
    }
  }
  modbus_set_byte_timeout(c.modbus, 0, kByteTimeoutMs * 1000);
  c.mapping = modbus_mapping_new_start_address(0, 0, 0, 0, 0, holding::count, 0, input::count);
  if (!c.mapping) throw std::runtime_error(where + ": " + modbus_strerror(errno));
  if (::pipe2(stop_pipe_, O_CLOEXEC) != 0) throw std::runtime_error(where + ": pipe: " + std::strerror(errno));
  thread_ = std::thread([this] { context_->tcp ? serve_tcp() : serve_rtu(); });
}

ModbusServer::~ModbusServer() {
  stopping_ = true;
  const char wake = 1;
  if (::write(stop_pipe_[1], &wake, 1) < 0) {
    // The thread also sees stopping_ within its poll timeout.
  }
  if (thread_.joinable()) thread_.join();
  ::close(stop_pipe_[0]);
  ::close(stop_pipe_[1]);
}

// One framed request: decoded by the register map, answered by libmodbus (the reply or an exception).
void ModbusServer::answer(int header_length, int trailer_length, const std::uint8_t* query, int length) {
  const int pdu_length = length - header_length - trailer_length;
  if (pdu_length < 1) return;
  std::uint16_t registers[125];
  std::size_t count = 0;
  const RegisterMap::Outcome outcome =
      mailbox_.serve(query + header_length, std::size_t(pdu_length), registers, &count);
  Context& c = *context_;
  if (outcome.exception != Exception::none) {
    modbus_reply_exception(c.modbus, query, unsigned(outcome.exception));
    return;
  }
  if (count > 0) {
    const std::uint16_t address = std::uint16_t((query[header_length + 1] << 8) | query[header_length + 2]);
    std::uint16_t* table = query[header_length] == kReadHoldingRegisters ? c.mapping->tab_registers
                                                                         : c.mapping->tab_input_registers;
    for (std::size_t i = 0; i < count; ++i) table[address + i] = registers[i];
  }
  modbus_reply(c.modbus, query, length, c.mapping);
}

void ModbusServer::serve_tcp() {
  Context& c = *context_;
  // The stop pipe, the listening socket, then one entry a client.
  std::vector<pollfd> watched{pollfd{stop_pipe_[0], POLLIN, 0}, pollfd{c.listen_socket, POLLIN, 0}};
  std::uint8_t query[MODBUS_TCP_MAX_ADU_LENGTH];
  const int header = modbus_get_header_length(c.modbus);
  while (!stopping_) {
    if (::poll(watched.data(), watched.size(), -1) < 0) {
      if (errno == EINTR) continue;
      return;
    }
    if (watched[0].revents) return;
    // Clients first: a request answered, or a client gone.
    for (std::size_t i = 2; i < watched.size();) {
      pollfd& client = watched[i];
      bool keep = true;
      if (client.revents & (POLLIN | POLLHUP | POLLERR)) {
        modbus_set_socket(c.modbus, client.fd);
        const int length = modbus_receive(c.modbus, query);
        if (length > 0) {
          answer(header, 0, query, length);
        } else if (length < 0) {
          keep = false;  // closed, broken, or a frame that stopped half way
        }
      }
      client.revents = 0;
      if (keep) {
        ++i;
      } else {
        ::close(client.fd);
        watched.erase(watched.begin() + std::ptrdiff_t(i));
      }
    }
    if (watched[1].revents & POLLIN) {
      const int client = ::accept4(c.listen_socket, nullptr, nullptr, SOCK_CLOEXEC);
      if (client >= 0) {
        if (watched.size() - 2 >= std::size_t(kMaxTcpClients)) {
          ::close(client);
        } else {
          watched.push_back(pollfd{client, POLLIN, 0});
        }
      }
    }
  }
  for (std::size_t i = 2; i < watched.size(); ++i) ::close(watched[i].fd);
}

void ModbusServer::serve_rtu() {
  Context& c = *context_;
  std::uint8_t query[MODBUS_RTU_MAX_ADU_LENGTH];
  const int header = modbus_get_header_length(c.modbus);
  const int line = modbus_get_socket(c.modbus);
  while (!stopping_) {
    pollfd watched[2] = {{stop_pipe_[0], POLLIN, 0}, {line, POLLIN, 0}};
    if (::poll(watched, 2, -1) < 0) {
      if (errno == EINTR) continue;
      return;
    }
    if (watched[0].revents) return;
    if (watched[1].revents & (POLLHUP | POLLERR) && !(watched[1].revents & POLLIN)) {
      ::usleep(10000);  // a pty whose other side is closed: wait for it to come back
      continue;
    }
    const int length = modbus_receive(c.modbus, query);
    if (length > 0) {
      answer(header, 2, query, length);
    } else if (length < 0) {
      modbus_flush(c.modbus);  // a broken frame: drop what is left of it
    }
  }
}

}  // namespace dynweigh::modbus

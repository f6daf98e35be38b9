// Modbus RTU server: one thread blocking in modbus_receive() with an
// indication timeout, so it notices Stop() within a fraction of a second.
#include <atomic>
#include <cerrno>
#include <cstring>
#include <thread>

#include "register_bank.h"
#include "relight/base/clock.h"
#include "relight/base/log.h"
#include "relight/hal/modbus_rtu_server.h"

namespace relight::hal {

struct ModbusRtuServer::Impl {
  ModbusRtuConfig config;
  RegisterBank& bank;
  modbus_t* ctx = nullptr;
  std::thread thread;
  std::atomic<bool> stop{false};

  Impl(ModbusRtuConfig c, RegisterBank& b) : config(std::move(c)), bank(b) {}

  void Run() {
    uint8_t req[MODBUS_RTU_MAX_ADU_LENGTH + 8];
    while (!stop.load()) {
      std::memset(req, 0, sizeof req);
      const int rc = modbus_receive(ctx, req);
      if (rc > 0) {
        if (!bank.HandleRequest(ctx, req, rc, 2, MonotonicUs())) modbus_flush(ctx);
      } else if (rc < 0 && errno != ETIMEDOUT) {
        // CRC error, a frame too short or too long: drop what is on the line.
        bank.bad_frames().fetch_add(1);
        modbus_flush(ctx);
      }
      // rc == 0: a request for another unit id; ETIMEDOUT: a quiet line.
    }
  }

  void Shutdown() {
    stop.store(true);
    if (thread.joinable()) thread.join();
    if (ctx != nullptr) {
      modbus_close(ctx);
      modbus_free(ctx);
    }
    ctx = nullptr;
  }
};

ModbusRtuServer::ModbusRtuServer(ModbusRtuConfig config, const RegisterMap& map, std::vector<uint16_t> initial)
    : ModbusServer(map, std::move(initial)), impl_(std::make_unique<Impl>(std::move(config), bank())) {}

ModbusRtuServer::~ModbusRtuServer() { impl_->Shutdown(); }

Status ModbusRtuServer::DoStart() {
  Impl& m = *impl_;
  m.Shutdown();
  const std::string where = "modbus-rtu: " + m.config.device;
  RELIGHT_RETURN_IF_ERROR(m.bank.Init());
  m.ctx = modbus_new_rtu(m.config.device.c_str(), m.config.baud, m.config.parity, m.config.data_bits,
                         m.config.stop_bits);
  if (m.ctx == nullptr) {
    return Status(StatusCode::kInvalidArgument, where + ": libmodbus refuses these line settings: " +
                                                    modbus_strerror(errno));
  }
  // Without a slave id an RTU server answers nothing (PITFALLS.md).
  if (modbus_set_slave(m.ctx, m.config.unit_id) != 0) {
    m.Shutdown();
    return Status(StatusCode::kInvalidArgument, where + ": unit_id " + std::to_string(m.config.unit_id) + " refused");
  }
  if (modbus_connect(m.ctx) != 0) {
    const int err = errno;
    m.Shutdown();
    return Status(err == ENOENT ? StatusCode::kNotFound : StatusCode::kIoError,
                  where + ": cannot open the serial device: " + std::strerror(err));
  }
  modbus_set_indication_timeout(m.ctx, 0, 200000);  // wake up to check Stop()
  modbus_set_byte_timeout(m.ctx, 0, 50000);         // a frame's bytes arrive back to back
  m.stop.store(false);
  m.thread = std::thread([&m] { m.Run(); });
  Log(LogLevel::kInfo, "modbus-rtu: serving unit %d on %s, %d baud %d%c%d", m.config.unit_id, m.config.device.c_str(),
      m.config.baud, m.config.data_bits, m.config.parity, m.config.stop_bits);
  return Status::Ok();
}

void ModbusRtuServer::DoStop() { impl_->Shutdown(); }

}  // namespace relight::hal

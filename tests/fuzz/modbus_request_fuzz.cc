// Fuzz target: a Modbus request as the TCP and RTU servers handle it
// (RegisterBank::HandleRequest): the PDU checked against the register map
// (CheckPdu), a legal write stored and decoded into parameter changes
// (RegisterInput::Collect -> RegisterMap::DecodeChanges), libmodbus's
// modbus_reply answering it. The first byte picks TCP (MBAP header) or RTU
// (slave address, CRC); the rest is the ADU as it came off the wire. The
// answer goes to /dev/null. The map: three fixtures, the standard block,
// a split 16-bit layout and a short one, as a patch gives them.
#include <fcntl.h>
#include <modbus/modbus.h>
#include <unistd.h>

#include <algorithm>
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <memory>
#include <vector>

#include "modbus/register_bank.h"
#include "relight/hal/patch.h"
#include "relight/hal/register_map.h"

namespace {

relight::hal::RegisterMap MakeMap() {
  static const char kPatch[] =
      "[[fixture]]\nname = \"a\"\nmodbus_base = 0\n"
      "[[fixture]]\nname = \"b\"\nmodbus_base = 8\n"
      "registers = [\"dimmer\", \"pan\", \"pan_fine\", \"tilt\", \"tilt_fine\", \"roll\", \"r\", \"g\", \"b\"]\n"
      "[[fixture]]\nname = \"c\"\nmodbus_base = 40\nregisters = [\"dimmer\", \"flags\"]\n";
  relight::hal::Patch patch;
  relight::hal::RegisterMap map;
  if (!relight::hal::ParsePatch(kPatch, "fuzz-map.toml", &patch).ok() ||
      !relight::hal::ResolvePatch({{"a"}, {"b"}, {"c"}}, &patch).ok() ||
      !relight::hal::RegisterMap::Build(patch.fixtures, &map).ok()) {
    std::abort();  // the harness's own patch must be valid
  }
  return map;
}

struct Server {
  modbus_t* ctx;
  int checksum_len;
  std::unique_ptr<relight::hal::RegisterBank> bank;
};

Server MakeServer(modbus_t* ctx, int checksum_len, const relight::hal::RegisterMap& map) {
  static const int null_fd = open("/dev/null", O_WRONLY);
  if (ctx == nullptr || null_fd < 0) std::abort();
  modbus_set_socket(ctx, null_fd);
  if (checksum_len != 0) modbus_set_slave(ctx, 1);
  Server s{ctx, checksum_len, std::make_unique<relight::hal::RegisterBank>(map, std::vector<uint16_t>())};
  if (!s.bank->Init().ok()) std::abort();
  return s;
}

// Modbus RTU's CRC-16 (polynomial 0xA001 reflected, start 0xFFFF), low byte first.
uint16_t Crc16(const uint8_t* p, size_t n) {
  uint16_t crc = 0xFFFF;
  for (size_t i = 0; i < n; ++i) {
    crc = static_cast<uint16_t>(crc ^ p[i]);
    for (int b = 0; b < 8; ++b) crc = (crc & 1) != 0 ? static_cast<uint16_t>((crc >> 1) ^ 0xA001) : static_cast<uint16_t>(crc >> 1);
  }
  return crc;
}

}  // namespace

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  static const relight::hal::RegisterMap map = MakeMap();
  static Server tcp = MakeServer(modbus_new_tcp("127.0.0.1", 1502), 0, map);
  static Server rtu = MakeServer(modbus_new_rtu("/dev/null", 19200, 'N', 8, 1), 2, map);
  if (size < 1) return 0;
  const bool is_rtu = (data[0] & 1) != 0;
  ++data;
  --size;
  // Padded as the servers pad: libmodbus may read a little past a short PDU.
  uint8_t req[MODBUS_MAX_ADU_LENGTH + 8] = {};
  size_t len = 0;
  if (is_rtu) {
    // What modbus_receive hands over: slave address, PDU, a good CRC (a bad
    // one never gets past libmodbus).
    if (size < 2 || size > MODBUS_RTU_MAX_ADU_LENGTH - 2) return 0;
    std::memcpy(req, data, size);
    const uint16_t crc = Crc16(req, size);
    req[size] = static_cast<uint8_t>(crc & 0xFF);
    req[size + 1] = static_cast<uint8_t>(crc >> 8);
    len = size + 2;
  } else {
    // The TCP server's framing (tcp_server.cc): protocol 0, a sane length,
    // the whole frame present; anything else closes the connection first.
    if (size < 7) return 0;
    const int protocol = (data[2] << 8) | data[3];
    const int length = (data[4] << 8) | data[5];
    if (protocol != 0 || length < 2 || length > MODBUS_TCP_MAX_ADU_LENGTH - 6) return 0;
    len = 6 + static_cast<size_t>(length);
    if (size < len) return 0;
    std::memcpy(req, data, len);
  }
  Server& server = is_rtu ? rtu : tcp;
  (void)server.bank->HandleRequest(server.ctx, req, static_cast<int>(len), server.checksum_len, 0);
  relight::ParamChange changes[3 * relight::kParamCount];
  while (server.bank->input().Collect(changes, 3 * relight::kParamCount) > 0) {
  }
  return 0;
}

// libFuzzer entry point: decode + validate of received PDU bytes (pdu/fuzz/decode_validate.h).
#include <cstddef>
#include <cstdint>

#include "log/log.h"
#include "pdu/fuzz/decode_validate.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dt::fuzz::DecodeValidateOne(data, size);
  return 0;
}

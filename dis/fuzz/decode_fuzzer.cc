// libFuzzer entry point: the DIS decoder and mapping on received datagrams (dis/fuzz/decode_one.h).
#include <cstddef>
#include <cstdint>

#include "dis/fuzz/decode_one.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  dt::dis::fuzz::DecodeOne(data, size);
  return 0;
}

// dds_sample_publisher: publishes the sample Construct PDU (feature 1:2:3, with a 4-byte trailer
// after the LCM encoding, as an authentication layer would add) over DDS every 100 ms for at
// most 30 s, so a DDS tool can be shown a live topic (dds_python_subscribe.py). Prints "ready"
// once its writer exists.
//   dds_sample_publisher <dds-url>
#include <chrono>
#include <cstdio>

#include "pdu/test/sample_pdus.h"
#include "transport/dds_transport.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: %s <dds-url>\n", argv[0]);
    return 2;
  }
  using namespace dt;
  try {
    DdsTransport t(ParseDdsUrl(argv[1]), sample::kSampleExercise);
    std::vector<uint8_t> bytes = EncodePdu(sample::Construct());
    for (int b : {0xA5, 0x5A, 0x01, 0x02}) bytes.push_back(static_cast<uint8_t>(b));
    std::printf("ready\n");
    std::fflush(stdout);
    const auto end = std::chrono::steady_clock::now() + std::chrono::seconds(30);
    while (std::chrono::steady_clock::now() < end) {
      if (Status s = t.Publish(PduType::kConstruct, bytes); !s) {
        std::fprintf(stderr, "publish: %s\n", s.error().message.c_str());
      }
      (void)t.HandleTimeout(100);
    }
    return 0;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "dds_sample_publisher: %s\n", e.what());
    return 1;
  }
}

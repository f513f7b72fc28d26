// pdu_capture: publishes one sample Construct PDU through PduBus over memq, captures the bytes
// as received, and writes them to <out>.bin with the expected field values in <out>.json, for
// the cross-language tests: decode_with_python.py (no key) and verify_mac_with_python.py (with a
// key file: the bus signs, and the JSON also gives the trailer's fields). Then a Construct and an
// Update published in one PduBus::Batch, captured as their batch in <out>_batch.bin.
#include <cstdio>
#include <fstream>
#include <stdexcept>
#include <vector>

#include <fmt/format.h>

#include "pdu/test/sample_pdus.h"
#include "transport/lcm_transport.h"
#include "transport/pdu_bus.h"

int main(int argc, char** argv) {
  if (argc != 2 && argc != 3) {
    std::fprintf(stderr, "usage: %s <output-prefix> [<key-file>]\n", argv[0]);
    return 2;
  }
  using namespace dt;
  // Fixed values for the trailer, so the reader can compare them.
  constexpr uint64_t kIncarnation = 1'764'000'000'123;
  constexpr int64_t kSendMs = 1'764'000'004'567;
  LcmTransport transport("memq://", sample::kSampleExercise);
  std::vector<uint8_t> captured, batch;
  transport.Subscribe(PduType::kBatch,
                      [&](std::span<const uint8_t> b) { batch.assign(b.begin(), b.end()); });
  transport.Subscribe(PduType::kConstruct,
                      [&](std::span<const uint8_t> b) { captured.assign(b.begin(), b.end()); });
  PduBusConfig config;
  config.exercise_id = sample::kSampleExercise;
  config.local = {1, 2};
  config.terrain_size_x_m = config.terrain_size_z_m = sample::kSampleTerrainM;
  config.clock = [] { return 0x80000001u; };
  if (argc == 3) {
    try {
      config.auth.key = ExerciseKey::FromFile(argv[2]);
    } catch (const std::exception& e) {
      std::fprintf(stderr, "%s\n", e.what());
      return 2;
    }
    config.auth.incarnation = kIncarnation;
    config.auth.wall_clock_ms = [] { return kSendMs; };
  }
  PduBus bus(transport, config);
  const dtpdu::construct_t pdu = sample::Construct();
  if (!bus.Publish(pdu).ok() || !transport.HandleTimeout(1000).ok() || captured.empty()) {
    std::fprintf(stderr, "capture failed\n");
    return 1;
  }
  {
    PduBus::Batch tick(bus);
    if (!bus.Publish(pdu).ok() || !bus.Publish(sample::Update()).ok()) return 1;
  }
  if (!transport.HandleTimeout(1000).ok() || batch.empty()) {
    std::fprintf(stderr, "batch capture failed\n");
    return 1;
  }
  std::ofstream(std::string(argv[1]) + "_batch.bin", std::ios::binary)
      .write(reinterpret_cast<const char*>(batch.data()),
             static_cast<std::streamsize>(batch.size()));
  std::ofstream(std::string(argv[1]) + ".bin", std::ios::binary)
      .write(reinterpret_cast<const char*>(captured.data()),
             static_cast<std::streamsize>(captured.size()));
  const std::string trailer =
      argc == 3
          ? fmt::format(R"(, "lcm_bytes": {}, "trailer": {{"sender": [1, 2], "incarnation": {},)"
                        R"( "sequence": 1, "send_time_ms": {}}})",
                        EncodePdu(pdu).size(), kIncarnation, kSendMs)
          : std::string();
  // %.17g: enough digits that Python's float() gives back the same double.
  std::ofstream(std::string(argv[1]) + ".json")
      << fmt::format(
             R"({{"fingerprint": "{:016x}", "exercise_id": {}, "pdu_type": {}, "timestamp_dis": {},)"
             R"( "sender": [1, 2], "sender_seq": 1, "origin": [{}, {}], "feature_number": {},)"
             R"( "feature_type": {}, "position_m": [{:.17g}, {:.17g}, {:.17g}], "length_m0": {:.17g},)"
             R"( "material": {}, "vertex_edits": [[{}, {}, {:.17g}], [{}, {}, {:.17g}]]{}}})",
             static_cast<uint64_t>(dtpdu::construct_t::getHash()), pdu.header.exercise_id,
             static_cast<int>(PduType::kConstruct), static_cast<int32_t>(0x80000001u),
             pdu.origin.site, pdu.origin.host, pdu.feature_number, pdu.feature_type,
             pdu.position_m[0], pdu.position_m[1], pdu.position_m[2], pdu.length_m[0], pdu.material,
             pdu.vertex_edits[0].spoke, pdu.vertex_edits[0].ring, pdu.vertex_edits[0].offset_m,
             pdu.vertex_edits[1].spoke, pdu.vertex_edits[1].ring, pdu.vertex_edits[1].offset_m,
             trailer)
      << "\n";
  return 0;
}

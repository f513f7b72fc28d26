// Writes a sample vehicle's Entity State (raw, or as a pcap of one UDP/3000 datagram) and
// decodes Entity States others wrote, printing the checked fields as JSON for the outside-peer
// tests (tshark_entity_state.py, opendis_entity_state.py).
//   dis_sample_tool encode <out.bin> | pcap <out.pcap> | features-pcap <out.pcap> |
//                   crater <out.bin> | bundle <out.bin> | bundle-pcap <out.pcap> |
//                   decode <in.bin> | decode-bundle <in.bin>
// features-pcap writes a crater, a bridge and a berm (Point, Point, Linear Object State) and
// prints one JSON line per PDU. bundle and bundle-pcap write one datagram bundling (IEEE
// 1278.2) the sample Entity State, a crater, a berm and the Entity State again, and print one
// JSON line per PDU (type, length, and for an Entity State its entity number). decode-bundle
// reads every Entity State of a bundling datagram, one JSON line each; any PDU refused fails.
#include <fmt/format.h>

#include <cstdio>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

#include "dis/dis_codec.h"
#include "dis/feature_mapping.h"
#include "dis/vehicle_mapping.h"

namespace {

using namespace dt::dis;

const GeodeticFrame& Frame() {
  static const GeodeticFrame frame({36.6, -121.9, 20.0});
  return frame;
}

VehiclePose SamplePose() {
  VehiclePose pose;
  pose.entity_id = {17, 23, 4242};
  pose.entity_type = {1, 1, 225, 1, 1, 3, 0};
  pose.force_id = 1;
  pose.marking = "DT-TANK-7";
  pose.position_m = {1523.25, 41.5, 2870.75};
  pose.attitude = {2.1, 0.05, -0.03};
  pose.velocity_mps = {4.0, 0.2, -3.0};
  pose.dead_reckoning = DeadReckoningAlgorithm::kRvw;
  return pose;
}

EntityStatePdu SamplePdu() { return ToEntityState(SamplePose(), Frame(), {7, 0x01000001}).value(); }

// The frame's origin and the sample's local attitude, for a peer's own conversion.
std::string SampleInputsJson() {
  const GeodeticOrigin& o = Frame().origin();
  const LocalAttitude a = SamplePose().attitude;
  const WorldCoordinates at_origin = Frame().ToGeocentric({0, 0, 0});
  return fmt::format("\"origin_x\": {:.17g}, \"origin_y\": {:.17g}, \"origin_z\": {:.17g}, ",
                     at_origin.x, at_origin.y, at_origin.z) +
         fmt::format(
             "\"origin_lat_deg\": {:.17g}, \"origin_lon_deg\": {:.17g}, \"origin_h_m\": {:.17g}, "
             "\"heading_rad\": {:.17g}, \"pitch_rad\": {:.17g}, \"roll_rad\": {:.17g}",
             o.latitude_deg, o.longitude_deg, o.height_m, a.heading_rad, a.pitch_rad, a.roll_rad);
}

std::string Json(const EntityStatePdu& p) {
  std::string marking;
  for (char c : p.marking.characters) {
    if (c == '\0') break;
    marking.push_back(c);
  }
  return fmt::format(
      "{{\"exercise\": {}, \"site\": {}, \"application\": {}, \"entity\": {}, \"force\": {}, "
      "\"x\": {:.17g}, \"y\": {:.17g}, \"z\": {:.17g}, \"psi\": {:.9g}, \"theta\": {:.9g}, "
      "\"phi\": {:.9g}, \"vx\": {:.9g}, \"vy\": {:.9g}, \"vz\": {:.9g}, "
      "\"dead_reckoning\": {}, \"marking_set\": {}, \"marking\": \"{}\", \"kind\": {}, "
      "\"domain\": {}, \"country\": {}, \"category\": {}}}",
      p.header.exercise_id, p.entity_id.site, p.entity_id.application, p.entity_id.entity,
      p.force_id, p.location.x, p.location.y, p.location.z, p.orientation.psi, p.orientation.theta,
      p.orientation.phi, p.linear_velocity.x, p.linear_velocity.y, p.linear_velocity.z,
      p.dead_reckoning.algorithm, p.marking.character_set, marking, p.entity_type.kind,
      p.entity_type.domain, p.entity_type.country, p.entity_type.category);
}

void Put16(std::vector<uint8_t>& b, uint16_t v) {  // big-endian, for IP and UDP
  b.push_back(static_cast<uint8_t>(v >> 8));
  b.push_back(static_cast<uint8_t>(v));
}
void PutLe32(std::vector<uint8_t>& b, uint32_t v) {  // the pcap file's own headers
  for (int i = 0; i < 4; ++i) b.push_back(static_cast<uint8_t>(v >> (8 * i)));
}
void PutLe16(std::vector<uint8_t>& b, uint16_t v) {
  b.push_back(static_cast<uint8_t>(v));
  b.push_back(static_cast<uint8_t>(v >> 8));
}

// An IPv4/UDP datagram 127.0.0.1:3000 -> 127.0.0.1:3000 (raw IP frame) holding the payload.
std::vector<uint8_t> IpFrame(const std::vector<uint8_t>& payload) {
  std::vector<uint8_t> ip;
  const auto total = static_cast<uint16_t>(20 + 8 + payload.size());
  ip.insert(ip.end(), {0x45, 0x00});
  Put16(ip, total);
  ip.insert(ip.end(), {0x00, 0x01, 0x40, 0x00, 64, 17, 0x00, 0x00, 127, 0, 0, 1, 127, 0, 0, 1});
  uint32_t sum = 0;
  for (size_t i = 0; i < 20; i += 2) sum += (uint32_t{ip[i]} << 8) | ip[i + 1];
  while (sum >> 16) sum = (sum & 0xFFFF) + (sum >> 16);
  const auto checksum = static_cast<uint16_t>(~sum);
  ip[10] = static_cast<uint8_t>(checksum >> 8);
  ip[11] = static_cast<uint8_t>(checksum);
  Put16(ip, 3000);
  Put16(ip, 3000);
  Put16(ip, static_cast<uint16_t>(8 + payload.size()));
  Put16(ip, 0);  // no UDP checksum (allowed over IPv4)
  ip.insert(ip.end(), payload.begin(), payload.end());
  return ip;
}

// A pcap file of raw IP frames, one per payload.
std::vector<uint8_t> Pcap(const std::vector<std::vector<uint8_t>>& payloads) {
  std::vector<uint8_t> file;
  PutLe32(file, 0xA1B2C3D4);
  PutLe16(file, 2);
  PutLe16(file, 4);
  PutLe32(file, 0);
  PutLe32(file, 0);
  PutLe32(file, 65535);
  PutLe32(file, 101);  // LINKTYPE_RAW: frames are IP packets
  uint32_t second = 1700000000;
  for (const auto& payload : payloads) {
    const std::vector<uint8_t> ip = IpFrame(payload);
    PutLe32(file, second++);
    PutLe32(file, 0);
    PutLe32(file, static_cast<uint32_t>(ip.size()));
    PutLe32(file, static_cast<uint32_t>(ip.size()));
    file.insert(file.end(), ip.begin(), ip.end());
  }
  return file;
}

bool WriteFile(const std::string& path, const std::vector<uint8_t>& bytes) {
  std::ofstream out(path, std::ios::binary);
  out.write(reinterpret_cast<const char*>(bytes.data()),
            static_cast<std::streamsize>(bytes.size()));
  return static_cast<bool>(out);
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::fprintf(stderr,
                 "usage: %s encode|pcap|features-pcap|crater|bundle|bundle-pcap <out> | "
                 "decode|decode-bundle <in>\n",
                 argv[0]);
    return 2;
  }
  const std::string mode = argv[1], path = argv[2];
  if (mode == "encode" || mode == "pcap") {
    const EntityStatePdu pdu = SamplePdu();
    const std::vector<uint8_t> bytes = Encode(pdu);
    if (!WriteFile(path, mode == "pcap" ? Pcap({bytes}) : bytes)) {
      std::fprintf(stderr, "cannot write %s\n", path.c_str());
      return 1;
    }
    std::string json = Json(pdu);
    json.pop_back();  // the closing brace
    std::printf("%s, %s}\n", json.c_str(), SampleInputsJson().c_str());
    return 0;
  }
  if (mode == "crater") {
    const auto pdu = FeatureToDis({17, 23, 5}, dt::FeatureParams::Crater(300, 400, 6.0), 12.0, 3,
                                  Frame(), {7, 0});
    const auto& point = std::get<PointObjectStatePdu>(pdu.value());
    if (!WriteFile(path, Encode(point))) {
      std::fprintf(stderr, "cannot write %s\n", path.c_str());
      return 1;
    }
    std::printf(
        "{\"site\": %u, \"application\": %u, \"object\": %u, \"update\": %u, "
        "\"domain\": %u, \"kind\": %u, \"category\": %u, \"x\": %.17g, \"y\": %.17g, "
        "\"z\": %.17g, \"specific\": %u, \"general\": %u}\n",
        point.object_id.site, point.object_id.application, point.object_id.entity,
        point.update_number, point.object_type.domain, point.object_type.kind,
        point.object_type.category, point.location.x, point.location.y, point.location.z,
        point.specific_appearance, point.general_appearance);
    return 0;
  }
  if (mode == "features-pcap") {
    const dt::FeatureId id{17, 23, 5};
    std::vector<std::vector<uint8_t>> payloads;
    for (const dt::FeatureParams& params :
         {dt::FeatureParams::Crater(300, 400, 6.0),
          dt::FeatureParams::Bridge(500, 100, 0.3, 8, 20, 60, 20, 5, 5),
          dt::FeatureParams::Berm(50, 60, 0.7, 40, 6, 2.5)}) {
      const auto pdu = FeatureToDis(id, params, 12.0, 1, Frame(), {7, 0});
      if (!pdu.ok()) {
        std::fprintf(stderr, "%s\n", pdu.error().message.c_str());
        return 1;
      }
      payloads.push_back(std::visit([](const auto& p) { return Encode(p); }, pdu.value()));
      std::printf("{\"pdu_type\": %d, \"length\": %zu}\n", payloads.back()[2],
                  payloads.back().size());
    }
    if (!WriteFile(path, Pcap(payloads))) {
      std::fprintf(stderr, "cannot write %s\n", path.c_str());
      return 1;
    }
    return 0;
  }
  if (mode == "bundle" || mode == "bundle-pcap") {
    std::vector<uint8_t> datagram;
    auto add = [&](const std::vector<uint8_t>& pdu, int entity) {
      datagram.insert(datagram.end(), pdu.begin(), pdu.end());
      std::printf("{\"pdu_type\": %d, \"length\": %zu, \"entity\": %d}\n", pdu[2], pdu.size(),
                  entity);
    };
    EntityStatePdu es = SamplePdu();
    add(Encode(es), es.entity_id.entity);
    const dt::FeatureId id{17, 23, 5};
    for (const dt::FeatureParams& params : {dt::FeatureParams::Crater(300, 400, 6.0),
                                            dt::FeatureParams::Berm(50, 60, 0.7, 40, 6, 2.5)}) {
      const auto pdu = FeatureToDis(id, params, 12.0, 1, Frame(), {7, 0});
      if (!pdu.ok()) {
        std::fprintf(stderr, "%s\n", pdu.error().message.c_str());
        return 1;
      }
      add(std::visit([](const auto& p) { return Encode(p); }, pdu.value()), -1);
    }
    ++es.entity_id.entity;
    add(Encode(es), es.entity_id.entity);
    if (!WriteFile(path, mode == "bundle-pcap" ? Pcap({datagram}) : datagram)) {
      std::fprintf(stderr, "cannot write %s\n", path.c_str());
      return 1;
    }
    return 0;
  }
  if (mode == "decode-bundle") {
    std::ifstream in(path, std::ios::binary);
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                     std::istreambuf_iterator<char>());
    Decoder decoder(7);
    int refused = 0;
    decoder.DecodeBundle(bytes, [&](const DecodeResult& r) {
      if (!r.ok()) {
        std::fprintf(stderr, "refused: %s\n", r.error().message.c_str());
        ++refused;
      } else if (const auto* es = std::get_if<EntityStatePdu>(&r.pdu())) {
        std::printf("%s\n", Json(*es).c_str());
      }
    });
    return refused == 0 ? 0 : 1;
  }
  if (mode == "decode") {
    std::ifstream in(path, std::ios::binary);
    const std::vector<uint8_t> bytes((std::istreambuf_iterator<char>(in)),
                                     std::istreambuf_iterator<char>());
    Decoder decoder(7);
    const DecodeResult r = decoder.Decode(bytes);
    if (!r.ok()) {
      std::fprintf(stderr, "refused (%s): %s\n",
                   std::string(DecodeFailureName(r.error().failure)).c_str(),
                   r.error().message.c_str());
      return 1;
    }
    const auto* es = std::get_if<EntityStatePdu>(&r.pdu());
    if (es == nullptr) {
      std::fprintf(stderr, "not an Entity State\n");
      return 1;
    }
    // The pose as a node would see it, too: the mapping must accept it.
    const auto pose = FromEntityState(*es, Frame());
    if (!pose.ok()) {
      std::fprintf(stderr, "mapping refused: %s\n", pose.error().message.c_str());
      return 1;
    }
    std::printf("%s\n", Json(*es).c_str());
    return 0;
  }
  std::fprintf(stderr, "unknown mode %s\n", mode.c_str());
  return 2;
}

// Tests ServerReplica: resuming from SQLite after a crash, a damaged database refused at start,
// export and import of terrain files (and of what is not one), and a full database reported
// rather than acknowledged.
#include "server/server_replica.h"

#include <sqlite3.h>
#include <sys/stat.h>
#include <unistd.h>

#include <filesystem>
#include <fstream>

#include <fmt/format.h>
#include <gtest/gtest.h>

#include "simulation/sim_cluster.h"
#include "simulation/sim_network.h"
#include "terrain/base_ground.h"
#include "terrain/terrain_digest.h"
#include "terrain/terrain_file.h"

namespace dt {
namespace {

const NodeAddress kServer{1, 100};
const NodeAddress kA{1, 1};

HeightGrid Ground() { return HeightGrid(33, 4.0, 10.0f); }

ReplicaConfig Config(NodeAddress address, NodeRole role) {
  ReplicaConfig c;
  c.address = address;
  c.role = role;
  c.max_feature_period_ms = 200;
  c.silence_ms = 800;
  c.playback_retry_ms = 300;
  c.playback_window = 64;
  return c;
}

// A server process and a node in one SimNetwork; the server can be crashed and reopened.
class ServerReplicaTest : public ::testing::Test {
 protected:
  ServerReplicaTest()
      : dir_(std::filesystem::temp_directory_path() /
             fmt::format("dt_server_replica_{}_{}", static_cast<long>(::getpid()),
                         ::testing::UnitTest::GetInstance()->current_test_info()->name())),
        net_(7) {
    std::filesystem::remove_all(dir_);
    std::filesystem::create_directories(dir_);
    node_transport_ = net_.Join(kA, 1);
    node_bus_ = std::make_unique<PduBus>(*node_transport_, BusConfig(kA));
    node_ = std::make_unique<Replica>(Config(kA, NodeRole::kNode), Ground(), *node_bus_);
    OpenServer();
    node_->SignOn(0);
    Run(2000);
  }
  ~ServerReplicaTest() override {
    CrashServer();
    node_.reset();
    node_bus_.reset();
    node_transport_.reset();
    std::filesystem::remove_all(dir_);
  }

  static PduBusConfig BusConfig(NodeAddress a) {
    PduBusConfig c;
    c.exercise_id = 1;
    c.local = a;
    c.terrain_size_x_m = c.terrain_size_z_m = 128.0;
    c.clock = [] { return 0u; };
    return c;
  }
  void OpenServer() {
    server_transport_ = net_.Join(kServer, 1);
    server_bus_ = std::make_unique<PduBus>(*server_transport_, BusConfig(kServer));
    auto s = ServerReplica::Open(Config(kServer, NodeRole::kServer), Ground(), *server_bus_,
                                 dir_ / "server.db");
    ASSERT_TRUE(s.ok()) << s.error().message;
    server_ = std::move(s).value();
    server_->replica().SignOn(net_.now_ms());
  }
  void CrashServer() {
    server_.reset();
    server_bus_.reset();
    server_transport_.reset();
  }
  void Run(int64_t ms) {
    for (int64_t t = 0; t < ms; t += 10) {
      net_.AdvanceMs(10);
      ASSERT_TRUE(node_bus_->HandleTimeout(0).ok());
      if (server_) {
        ASSERT_TRUE(server_bus_->HandleTimeout(0).ok());
      }
      node_->Tick(net_.now_ms());
      if (server_) server_->replica().Tick(net_.now_ms());
    }
  }

  std::filesystem::path dir_;
  SimNetwork net_;
  std::unique_ptr<Transport> node_transport_, server_transport_;
  std::unique_ptr<PduBus> node_bus_, server_bus_;
  std::unique_ptr<Replica> node_;
  std::unique_ptr<ServerReplica> server_;
};

TEST_F(ServerReplicaTest, ARestartedServerHasEverythingItAcknowledged) {
  ASSERT_TRUE(node_->signed_on());
  for (int i = 0; i < 10; ++i) {
    ASSERT_TRUE(node_->Create(FeatureParams::Crater(10 + 10 * i, 50, 3)).ok());
  }
  Run(500);
  ASSERT_EQ(node_->acknowledged_change_seq(), 10);
  const std::string digest = node_->Digest();
  CrashServer();
  OpenServer();
  EXPECT_EQ(server_->replica().Digest(), digest);  // before any message: from the database
  EXPECT_EQ(server_->replica().live_feature_count(), 10u);
  Run(1000);
  EXPECT_EQ(server_->replica().Digest(), node_->Digest());
}

TEST_F(ServerReplicaTest, ARestartedServerKeepsEveryEarthMove) {
  ASSERT_TRUE(node_->signed_on());
  // A cut and the pile beside it, then more blade work over the same posts.
  for (int i = 0; i < 12; ++i) {
    const auto k = static_cast<uint16_t>(4 + i);
    ASSERT_TRUE(
        node_->Create(FeatureParams::EarthMove({{k, 10, -300 - i}, {k, 12, 300 + i}})).ok());
  }
  ASSERT_TRUE(node_->Create(FeatureParams::Crater(30, 40, 5)).ok());
  Run(500);
  ASSERT_EQ(node_->acknowledged_change_seq(), 13);
  const std::string digest = node_->Digest();
  CrashServer();
  OpenServer();
  // Before any message, from the database: every post's sum and the digest.
  EXPECT_EQ(server_->replica().Digest(), digest);
  EXPECT_EQ(server_->replica().terrain().BladeDeltaMm(9, 10), -305);
  EXPECT_EQ(server_->replica().terrain().BladeDeltaMm(15, 12), 311);
  EXPECT_EQ(server_->replica().terrain().ground().post(9, 10),
            node_->terrain().ground().post(9, 10));
  Run(1000);
  EXPECT_EQ(server_->replica().Digest(), node_->Digest());
}

TEST_F(ServerReplicaTest, ExportThenImportMovesTheExercise) {
  ASSERT_TRUE(node_->Create(FeatureParams::Crater(30, 30, 4)).ok());
  ASSERT_TRUE(node_->Create(FeatureParams::Berm(60, 60, 0.3, 20, 4, 2)).ok());
  Run(500);
  const auto file = dir_ / "exercise.dtt";
  ASSERT_TRUE(server_->ExportTerrain(file).ok());
  auto loaded = LoadTerrain(file);
  ASSERT_TRUE(loaded.ok());
  EXPECT_EQ(loaded.value()->feature_count(), 2u);

  // A new exercise (fresh database) imports the file; its node receives the features.
  CrashServer();
  std::filesystem::remove(dir_ / "server.db");
  node_.reset();
  node_bus_.reset();
  node_transport_.reset();
  node_transport_ = net_.Join({1, 3}, 1);
  node_bus_ = std::make_unique<PduBus>(*node_transport_, BusConfig({1, 3}));
  node_ = std::make_unique<Replica>(Config({1, 3}, NodeRole::kNode), Ground(), *node_bus_);
  OpenServer();
  node_->SignOn(net_.now_ms());
  ASSERT_TRUE(server_->ImportTerrain(file).ok());
  Run(1500);
  EXPECT_EQ(node_->counters().rejected, 0u);
  EXPECT_EQ(server_->replica().counters().sent, 2u);
  EXPECT_EQ(node_->live_feature_count(), 2u);
  EXPECT_EQ(node_->Digest(), server_->replica().Digest());
  EXPECT_EQ(server_->store().LoadAll().value().size(), 2u);

  // A file with other ground is refused as a whole.
  Terrain other(HeightGrid(33, 4.0, 3.0f));
  ASSERT_TRUE(other.Add({1, 9, 1}, FeatureParams::Crater(20, 20, 2)).ok());
  ASSERT_TRUE(SaveTerrain(other, dir_ / "other.dtt").ok());
  EXPECT_FALSE(server_->ImportTerrain(dir_ / "other.dtt").ok());
  EXPECT_EQ(server_->replica().live_feature_count(), 2u);
}

TEST_F(ServerReplicaTest, ADamagedDatabaseStopsTheStartNamingTheRow) {
  ASSERT_TRUE(node_->Create(FeatureParams::Crater(30, 30, 4)).ok());
  ASSERT_TRUE(node_->Create(FeatureParams::Crater(60, 60, 4)).ok());
  Run(500);
  ASSERT_EQ(node_->acknowledged_change_seq(), 2);
  CrashServer();
  {
    sqlite3* db = nullptr;
    ASSERT_EQ(sqlite3_open((dir_ / "server.db").c_str(), &db), SQLITE_OK);
    // One bit of change 2's parameter bytes (its position), as a failing disk might flip it.
    ASSERT_EQ(sqlite3_exec(db,
                           "UPDATE changes SET params = CAST(substr(params, 1, 2) || X'01' ||"
                           " substr(params, 4) AS BLOB) WHERE seq = 2;",
                           nullptr, nullptr, nullptr),
              SQLITE_OK);
    sqlite3_close(db);
  }
  server_transport_ = net_.Join(kServer, 1);
  server_bus_ = std::make_unique<PduBus>(*server_transport_, BusConfig(kServer));
  auto s = ServerReplica::Open(Config(kServer, NodeRole::kServer), Ground(), *server_bus_,
                               dir_ / "server.db");
  ASSERT_FALSE(s.ok());
  EXPECT_NE(s.error().message.find((dir_ / "server.db").string() + ": row author 1:1 change_seq 2"),
            std::string::npos)
      << s.error().message;
  EXPECT_NE(s.error().message.find("checksum mismatch"), std::string::npos) << s.error().message;
}

TEST_F(ServerReplicaTest, ImportRefusesWhatIsNotAWholeTerrainFileAndAppliesNothing) {
  ASSERT_TRUE(node_->Create(FeatureParams::Crater(30, 30, 4)).ok());
  Run(500);
  const auto good = dir_ / "good.dtt";
  ASSERT_TRUE(server_->ExportTerrain(good).ok());
  const auto bytes = EncodeTerrainFile(server_->replica().terrain());

  std::filesystem::create_directory(dir_ / "dir.dtt");
  ASSERT_EQ(mkfifo((dir_ / "fifo.dtt").c_str(), 0600), 0);  // no writer
  std::ofstream(dir_ / "big.dtt").close();
  std::filesystem::resize_file(dir_ / "big.dtt", kMaxTerrainFileBytes + 1);
  std::ofstream(dir_ / "empty.dtt").close();
  {
    std::ofstream cut(dir_ / "cut.dtt", std::ios::binary);
    cut.write(reinterpret_cast<const char*>(bytes.data()),
              static_cast<std::streamsize>(bytes.size() - 1));
  }
  const int64_t own_changes = server_->replica().own_change_seq();
  const size_t stored = server_->store().LoadAll().value().size();
  const std::string digest = server_->replica().Digest();
  const std::pair<std::filesystem::path, std::string> cases[] = {
      {dir_ / "dir.dtt", "is a directory"},
      {dir_ / "fifo.dtt", "is a FIFO"},  // returns at once: a blocking open would wait here
      {"/dev/zero", "is a character device"},
      {dir_ / "big.dtt", "over the limit"},
      {dir_ / "empty.dtt", "file is 0 bytes"},
      {dir_ / "cut.dtt", "does not match the file size"},
  };
  for (const auto& [path, reason] : cases) {
    const Status s = server_->ImportTerrain(path);
    ASSERT_FALSE(s.ok()) << path;
    EXPECT_NE(s.error().message.find(path.string() + ": "), std::string::npos) << s.error().message;
    EXPECT_NE(s.error().message.find(reason), std::string::npos) << s.error().message;
  }
  Run(300);
  EXPECT_EQ(server_->replica().own_change_seq(), own_changes);
  EXPECT_EQ(server_->store().LoadAll().value().size(), stored);
  EXPECT_EQ(server_->replica().Digest(), digest);
  EXPECT_EQ(node_->Digest(), digest);

  // Export refuses to replace a FIFO (or anything but a regular file) and leaves it.
  const Status to_fifo = server_->ExportTerrain(dir_ / "fifo.dtt");
  ASSERT_FALSE(to_fifo.ok());
  EXPECT_NE(to_fifo.error().message.find("is a FIFO"), std::string::npos)
      << to_fifo.error().message;
  EXPECT_TRUE(std::filesystem::is_fifo(dir_ / "fifo.dtt"));
}

TEST_F(ServerReplicaTest, AFullDatabaseIsReportedAndNothingIsAcknowledged) {
  ASSERT_TRUE(server_->store().LimitPages(1).ok());
  for (int i = 0; i < 60; ++i) {
    ASSERT_TRUE(node_->Create(FeatureParams::Crater(10 + i, 50, 2)).ok());
  }
  Run(600);
  EXPECT_FALSE(server_->replica().store_status().ok());
  EXPECT_FALSE(server_->Flush().ok());
  EXPECT_EQ(node_->acknowledged_change_seq(), 0);
  ASSERT_TRUE(server_->store().LimitPages(1 << 20).ok());  // space freed
  Run(600);
  EXPECT_TRUE(server_->replica().store_status().ok());
  EXPECT_EQ(node_->acknowledged_change_seq(), 60);
}

}  // namespace
}  // namespace dt

namespace dt {
namespace {

// docs/node.md "Starting from a saved terrain": the database records the ground its exercise is
// held on; a server started on another ground refuses it, naming both digests and sources.
TEST_F(ServerReplicaTest, ADatabaseFromAnotherGroundIsRefusedNamingBothGrounds) {
  ASSERT_TRUE(node_->Create(FeatureParams::Crater(40, 40, 3)).ok());
  Run(500);
  CrashServer();
  {
    auto store = SqliteChangeStore::Open(dir_ / "server.db", 128.0, 128.0);
    ASSERT_TRUE(store.ok()) << store.error().message;
    auto recorded = store.value()->LoadGround();
    ASSERT_TRUE(recorded.ok()) << recorded.error().message;
    ASSERT_TRUE(recorded.value().has_value());
    EXPECT_EQ(recorded.value()->digest, ComputeDigest(Ground()).ToHex());
    EXPECT_EQ(recorded.value()->source, "the given ground");  // ReplicaConfig's default
  }
  server_transport_ = net_.Join(kServer, 1);
  server_bus_ = std::make_unique<PduBus>(*server_transport_, BusConfig(kServer));
  ReplicaConfig config = Config(kServer, NodeRole::kServer);
  config.ground_source = "ground_file /grounds/other.dtt";
  const HeightGrid other(33, 4.0, 11.0f);
  auto refused = ServerReplica::Open(config, other, *server_bus_, dir_ / "server.db");
  ASSERT_FALSE(refused.ok());
  const std::string& m = refused.error().message;
  EXPECT_NE(m.find((dir_ / "server.db").string()), std::string::npos) << m;
  EXPECT_NE(m.find(ComputeDigest(Ground()).ToHex()), std::string::npos) << m;
  EXPECT_NE(m.find(ComputeDigest(other).ToHex()), std::string::npos) << m;
  EXPECT_NE(m.find("the given ground"), std::string::npos) << m;
  EXPECT_NE(m.find("ground_file /grounds/other.dtt"), std::string::npos) << m;
  // The same ground opens it again, with everything it held.
  server_bus_.reset();
  server_transport_.reset();
  OpenServer();
  EXPECT_EQ(server_->replica().live_feature_count(), 1u);
}

// The server hashes its ground once, for the database's check, and hands that digest to its
// replica: the replica's ground digest is the one it would have worked out itself, base features
// included, and the one the database records.
TEST_F(ServerReplicaTest, TheReplicaTakesTheDigestTheServerCheckedAndItIsTheSame) {
  Terrain shaped(Ground());
  ASSERT_TRUE(shaped.Add({9, 9, 1}, FeatureParams::Crater(60, 60, 5)).ok());
  const BaseGround base = BaseGroundFromTerrain(shaped);
  ASSERT_EQ(base.features.size(), 1u);
  auto transport = net_.Join({1, 101}, 1);
  PduBus bus(*transport, BusConfig({1, 101}));
  auto opened =
      ServerReplica::Open(Config({1, 101}, NodeRole::kServer), base, bus, dir_ / "based.db");
  ASSERT_TRUE(opened.ok()) << opened.error().message;
  auto own_transport = net_.Join({1, 102}, 1);
  PduBus own_bus(*own_transport, BusConfig({1, 102}));
  const Replica own(Config({1, 102}, NodeRole::kNode), base, own_bus);  // digests it itself
  EXPECT_EQ(opened.value()->replica().ground_digest(), own.ground_digest());
  EXPECT_NE(own.ground_digest(), ComputeDigest(Ground()));  // the base feature counts
  auto recorded = opened.value()->store().LoadGround();
  ASSERT_TRUE(recorded.ok()) << recorded.error().message;
  ASSERT_TRUE(recorded.value().has_value());
  EXPECT_EQ(recorded.value()->digest, own.ground_digest().ToHex());
}

}  // namespace
}  // namespace dt

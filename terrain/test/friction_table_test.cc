#include "terrain/friction_table.h"

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <stdexcept>
#include <string>
#include <vector>

#include <gtest/gtest.h>

namespace dt {
namespace {

namespace fs = std::filesystem;

const fs::path kShipped = fs::path(DT_SOURCE_DIR) / "configs" / "friction.toml";

// A complete, valid config with the given classes; `extra` is appended.
std::string Config(const std::string& extra = "") {
  std::string text = "classes = [\"tracked\", \"wheeled\"]\n[vehicles]\ntank = \"tracked\"\n";
  for (uint16_t m = 1; m < kMaterialCount; ++m) {
    text += "[friction." + std::string(MaterialName(static_cast<Material>(m))) + "]\n";
    text += "tracked = { static = 0.8, dynamic = 0.6 }\n";
    text += "wheeled = { static = 0.7, dynamic = 0.5 }\n";
  }
  return text + extra;
}

// Replaces the first occurrence of `from` in the valid config.
std::string ConfigWith(const std::string& from, const std::string& to) {
  std::string text = Config();
  const size_t at = text.find(from);
  EXPECT_NE(at, std::string::npos) << from;
  return text.replace(at, from.size(), to);
}

void ExpectThrows(const std::string& text, const std::vector<std::string>& fragments) {
  try {
    (void)FrictionTable::Parse(text, "bad.toml");
    ADD_FAILURE() << "no exception for:\n" << text;
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    EXPECT_EQ(message.rfind("bad.toml", 0), 0u) << message;
    for (const auto& f : fragments) {
      EXPECT_NE(message.find(f), std::string::npos) << "message: " << message << "\nwant: " << f;
    }
  }
}

// Every built-in vehicle type having a class is checked beside the types (vehicle/test).
TEST(FrictionTableTest, ShippedConfigCoversEveryMaterial) {
  const FrictionTable t = FrictionTable::LoadFile(kShipped);
  EXPECT_EQ(t.classes(), (std::vector<std::string>{"tracked", "wheeled"}));
  EXPECT_EQ(t.ClassOf("tank"), "tracked");
  EXPECT_EQ(t.ClassOf("truck"), "wheeled");
  EXPECT_EQ(t.ClassOf("jeep"), "wheeled");
  for (uint16_t m = 1; m < kMaterialCount; ++m) {
    for (const auto& cls : t.classes()) {
      const Friction f = t.Lookup(static_cast<Material>(m), cls);
      EXPECT_GT(f.dynamic_coefficient, 0.0);
      EXPECT_LE(f.dynamic_coefficient, f.static_coefficient);
      EXPECT_LE(f.static_coefficient, kMaxFrictionCoefficient);
    }
  }
  // Wheels lose more grip in mud than tracks do.
  EXPECT_LT(t.LookupForVehicle(Material::kMud, "jeep").static_coefficient,
            t.LookupForVehicle(Material::kMud, "tank").static_coefficient);
}

TEST(FrictionTableTest, LookupReturnsTheConfiguredPair) {
  const FrictionTable t =
      FrictionTable::Parse(ConfigWith("[friction.sand]\ntracked = { static = 0.8, dynamic = 0.6 }",
                                      "[friction.sand]\ntracked = { static = 1, dynamic = 0.25 }"),
                           "mem");
  EXPECT_EQ(t.Lookup(Material::kSand, "tracked"), (Friction{1.0, 0.25}));
  EXPECT_EQ(t.Lookup(Material::kSand, "wheeled"), (Friction{0.7, 0.5}));
  EXPECT_EQ(t.Lookup(Material::kSteel, "tracked"), (Friction{0.8, 0.6}));
  EXPECT_EQ(t.LookupForVehicle(Material::kSand, "tank"), (Friction{1.0, 0.25}));
}

TEST(FrictionTableTest, MisuseThrows) {
  const FrictionTable t = FrictionTable::Parse(Config(), "mem");
  EXPECT_THROW((void)t.Lookup(Material::kFromGround, "tracked"), std::invalid_argument);
  EXPECT_THROW((void)t.Lookup(static_cast<Material>(77), "tracked"), std::invalid_argument);
  EXPECT_THROW((void)t.Lookup(Material::kGrass, "hover"), std::invalid_argument);
  try {
    (void)t.ClassOf("truck");
    ADD_FAILURE() << "truck is not mapped in this config";
  } catch (const std::invalid_argument& e) {
    EXPECT_NE(std::string(e.what()).find("vehicle type 'truck'"), std::string::npos) << e.what();
  }
}

TEST(FrictionTableTest, BadConfigsNameKeyAndValue) {
  ExpectThrows("classes = [", {"not valid TOML"});
  ExpectThrows(ConfigWith("classes", "colour = \"red\"\nclasses"),
               {"colour = 'red'", "unknown key"});
  // A key after the last table (the last material's) belongs to it.
  const std::string last(MaterialName(static_cast<Material>(kMaterialCount - 1)));
  ExpectThrows(Config("colour = \"red\"\n"),
               {"friction." + last + ".colour = 'red'", "not one of the listed classes"});
  ExpectThrows(ConfigWith("classes = [\"tracked\", \"wheeled\"]\n", ""), {"classes is missing"});
  ExpectThrows(ConfigWith("classes = [\"tracked\", \"wheeled\"]", "classes = []"),
               {"classes = []", "non-empty array"});
  ExpectThrows(ConfigWith("classes = [\"tracked\", \"wheeled\"]", "classes = [\"tracked\", 3]"),
               {"classes = 3", "non-empty string"});
  ExpectThrows(ConfigWith("classes = [\"tracked\", \"wheeled\"]",
                          "classes = [\"tracked\", \"wheeled\", \"tracked\"]"),
               {"classes = 'tracked'", "listed twice"});
  ExpectThrows(ConfigWith("tank = \"tracked\"", "tank = \"legs\""),
               {"vehicles.tank = 'legs'", "not one of the listed classes"});
  ExpectThrows(ConfigWith("tank = \"tracked\"", "tank = 1"), {"vehicles.tank = 1"});
  ExpectThrows(Config("[friction.lava]\ntracked = { static = 0.8, dynamic = 0.6 }\n"),
               {"friction.lava", "is not a material"});
  ExpectThrows(ConfigWith("[friction.mud]", "[friction.from_ground]"),
               {"friction.from_ground", "is not a material"});
  ExpectThrows(ConfigWith("[friction.mud]", "[friction_mud]"), {"unknown key"});
  ExpectThrows(ConfigWith("[friction.gravel]\ntracked = { static = 0.8, dynamic = 0.6 }\n",
                          "[friction.gravel]\n"),
               {"friction.gravel.tracked is missing"});
  ExpectThrows(ConfigWith("[friction.rock]\ntracked", "[friction.rock]\nlegs = 1\ntracked"),
               {"friction.rock.legs = 1", "not one of the listed classes"});
  ExpectThrows(ConfigWith("tracked = { static = 0.8, dynamic = 0.6 }", "tracked = 0.8"),
               {"friction.grass.tracked = 0.8", "must be a table"});
  ExpectThrows(ConfigWith("static = 0.8", "static = \"high\""),
               {"friction.grass.tracked.static = 'high'", "must be a number"});
  ExpectThrows(ConfigWith("static = 0.8", "static = true"),
               {"friction.grass.tracked.static = true", "must be a number"});
  ExpectThrows(ConfigWith("static = 0.8", "static = 2.5"),
               {"friction.grass.tracked.static = 2.5", "must be in (0, 2]"});
  ExpectThrows(ConfigWith("dynamic = 0.6", "dynamic = 0"),
               {"friction.grass.tracked.dynamic = 0", "must be in (0, 2]"});
  ExpectThrows(ConfigWith("dynamic = 0.6", "dynamic = nan"),
               {"friction.grass.tracked.dynamic = nan", "must be in (0, 2]"});
  ExpectThrows(ConfigWith("static = 0.8, dynamic = 0.6", "static = 0.5, dynamic = 0.6"),
               {"friction.grass.tracked = ", "must not exceed static"});
  ExpectThrows(ConfigWith("static = 0.8, dynamic = 0.6", "static = 0.8"),
               {"friction.grass.tracked.dynamic is missing"});
  ExpectThrows(ConfigWith("static = 0.8, dynamic = 0.6", "static = 0.8, dynamic = 0.6, mu = 1"),
               {"friction.grass.tracked.mu = 1", "unknown key"});
  // Every material must be present.
  std::string no_asphalt = Config();
  const size_t at = no_asphalt.find("[friction.asphalt]");
  no_asphalt.erase(at, no_asphalt.find("[friction.steel]") - at);
  ExpectThrows(no_asphalt, {"friction.asphalt is missing"});
}

TEST(FrictionTableTest, LoadFileNamesTheFile) {
  std::string pattern = (fs::temp_directory_path() / "dt_friction_XXXXXX").string();
  ASSERT_NE(mkdtemp(pattern.data()), nullptr);
  const fs::path dir = pattern;
  const fs::path bad = dir / "friction.toml";
  std::ofstream(bad) << ConfigWith("static = 0.8", "static = -1");
  try {
    (void)FrictionTable::LoadFile(bad);
    ADD_FAILURE() << "no exception";
  } catch (const std::invalid_argument& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(bad.string()), std::string::npos) << message;
    EXPECT_NE(message.find("friction.grass.tracked.static = -1"), std::string::npos) << message;
  }
  EXPECT_THROW((void)FrictionTable::LoadFile(dir / "absent.toml"), std::invalid_argument);
  fs::remove_all(dir);
}

}  // namespace
}  // namespace dt

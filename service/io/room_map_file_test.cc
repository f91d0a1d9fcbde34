// Room map and mount files: the README's example parses to the rooms and corners it describes;
// each kind of bad file is refused with its line and field.
#include "service/io/room_map_file.h"

#include <gtest/gtest.h>

#include <fstream>
#include <sstream>

namespace monocle {
namespace {

std::string ReadExample(const std::string& name) {
  std::ifstream in(std::string(MONOCLE_SOURCE_DIR) + "/idl/examples/" + name);
  std::stringstream s;
  s << in.rdbuf();
  return s.str();
}

const MapCorner* FindCorner(const RoomMap& map, const std::string& id) {
  for (const auto& room : map.rooms)
    for (const auto& c : room.corners)
      if (c.id == id) return &c;
  return nullptr;
}

TEST(RoomMapFileTest, TheExampleMapHasAnLShapedHallAndAStoreRoom) {
  const auto map =
      LoadRoomMapFile(std::string(MONOCLE_SOURCE_DIR) + "/idl/examples/room_map.pbtxt");
  ASSERT_TRUE(map.ok()) << map.error();
  ASSERT_EQ(map->rooms.size(), 2u);
  EXPECT_EQ(map->rooms[0].id, "hall");
  EXPECT_EQ(map->rooms[0].corners.size(), 5u);
  EXPECT_EQ(FindCorner(*map, "hall-3"), nullptr) << "the reflex vertex is no corner";
  const MapCorner* far = FindCorner(*map, "hall-1");
  ASSERT_NE(far, nullptr);
  EXPECT_EQ(far->position_m, Eigen::Vector2d(7, 0));
  EXPECT_DOUBLE_EQ(far->ceiling_height_m, 2.6);
  ASSERT_EQ(map->rooms[1].corners.size(), 2u);
  const MapCorner* door = FindCorner(*map, "store-door");
  ASSERT_NE(door, nullptr);
  EXPECT_EQ(door->room_id, "store");
  EXPECT_DOUBLE_EQ(door->ceiling_height_m, 2.4);
  // X x Y points down (the corner frame's Z): X along the wall x = 8, Y along y = 0.
  EXPECT_NEAR(door->x_edge.x() * door->y_edge.y() - door->x_edge.y() * door->y_edge.x(), -1, 1e-12);

  const auto mount = ParseCameraMount(ReadExample("camera_mount.pbtxt"), "mount.pbtxt", *map);
  ASSERT_TRUE(mount.ok()) << mount.error();
  EXPECT_DOUBLE_EQ(mount->translation.z(), 0.4);
  // The optical axis looks ahead and up, 50 degrees from the vertical.
  const Eigen::Vector3d axis = mount->rotation * Eigen::Vector3d::UnitZ();
  EXPECT_NEAR(std::acos(axis.z()) * 180 / M_PI, 50, 1e-4);
  EXPECT_GT(axis.x(), 0);
}

TEST(RoomMapFileTest, AClockwiseOutlineIsTurnedRound) {
  const auto map = ParseRoomMap(R"(room { id: "r" ceiling_height_m: 2.5
    outline { x_m: 0 y_m: 0 } outline { x_m: 0 y_m: 4 } outline { x_m: 5 y_m: 4 }
    outline { x_m: 5 y_m: 0 } })",
                                "cw.pbtxt");
  ASSERT_TRUE(map.ok()) << map.error();
  EXPECT_GT(SignedDoubleArea(map->rooms[0].outline_m), 0);
  EXPECT_EQ(map->rooms[0].corners.size(), 4u);
}

struct BadMap {
  const char* what;
  const char* text;
  const char* expected;  // in the message, line included
};

class BadRoomMapTest : public ::testing::TestWithParam<BadMap> {};

TEST_P(BadRoomMapTest, IsRefusedWithTheLineAndTheField) {
  const auto map = ParseRoomMap(GetParam().text, "bad.pbtxt");
  ASSERT_FALSE(map.ok()) << GetParam().what;
  EXPECT_NE(map.error().message.find(GetParam().expected), std::string::npos)
      << GetParam().what << ": " << map.error().message;
}

INSTANTIATE_TEST_SUITE_P(
    Files, BadRoomMapTest,
    ::testing::Values(
        BadMap{"a corner outside the room",
               "room { id: \"r\" ceiling_height_m: 2.5\n"
               "  outline { x_m: 0 y_m: 0 } outline { x_m: 4 y_m: 0 }\n"
               "  outline { x_m: 4 y_m: 4 } outline { x_m: 0 y_m: 4 }\n"
               "  corner { id: \"c\" position { x_m: 6 y_m: 1 } } }",
               "line 4: room[0].corner[0].position lies outside the room and is not a vertex of "
               "room[0].outline (the nearest is 2.24 m away)"},
        BadMap{"corners that do not match the outline (an edge across the room)",
               "room { id: \"r\" ceiling_height_m: 2.5\n"
               "  outline { x_m: 0 y_m: 0 } outline { x_m: 4 y_m: 0 }\n"
               "  outline { x_m: 4 y_m: 4 } outline { x_m: 0 y_m: 4 }\n"
               "  corner { id: \"c\" position { x_m: 0 y_m: 0 }\n"
               "    edge_heading_deg: [0, 45] } }",
               "line 5: room[0].corner[0].edge_heading_deg[1] does not run along a wall of the "
               "outline "
               "from this corner (the walls run at 90 and 0 degrees)"},
        BadMap{"a corner at a vertex that is no right angle",
               "room { id: \"r\" ceiling_height_m: 2.5\n"
               "  outline { x_m: 0 y_m: 0 } outline { x_m: 4 y_m: 0 }\n"
               "  outline { x_m: 2 y_m: 3 }\n"
               "  corner { position { x_m: 2 y_m: 3 } } }",
               "line 4: room[0].corner[0].position is a vertex where the walls do not meet"},
        BadMap{"a bow-tie outline",
               "room { id: \"r\" ceiling_height_m: 2.5\n"
               "  outline { x_m: 0 y_m: 0 } outline { x_m: 2 y_m: 2 }\n"
               "  outline { x_m: 2 y_m: 0 } outline { x_m: 0 y_m: 2 } }",
               "line 2: room[0].outline crosses itself"},
        BadMap{"no ceiling height", "room { id: \"r\"\n outline { x_m: 0 y_m: 0 } }",
               "line 1: room[0].ceiling_height_m must be the floor-to-ceiling height"},
        BadMap{"two rooms of one name",
               "room { id: \"a\" ceiling_height_m: 2.5 outline { x_m: 0 y_m: 0 }\n"
               "  outline { x_m: 4 y_m: 0 } outline { x_m: 4 y_m: 4 } outline { x_m: 0 y_m: 4 } }\n"
               "room { id: \"a\" ceiling_height_m: 2.5 outline { x_m: 9 y_m: 0 }\n"
               "  outline { x_m: 12 y_m: 0 } outline { x_m: 12 y_m: 4 } outline { x_m: 9 y_m: 4 } "
               "}",
               "line 3: room[1].id 'a' names two rooms"},
        BadMap{"an unknown field", "room { id: \"r\" ceiling_height: 2.5 }",
               "line 1, column 30: Message type \"monocle.proto.Room\" has no field named "
               "\"ceiling_height\""},
        BadMap{"an empty map", "", "no room"}));

TEST(CameraMountFileTest, AMountAtOrAboveACeilingIsRefusedWithTheField) {
  RoomMap map;
  map.rooms.push_back({"low", {{0, 0}, {4, 0}, {4, 4}, {0, 4}}, 2.2, {}});
  const auto high = ParseCameraMount(
      "translation_m: [0, 0, 2.5]\n"
      "rotation_xyzw: [0, 0, 0, 1]\n",
      "mount.pbtxt", map);
  ASSERT_FALSE(high.ok());
  EXPECT_NE(high.error().message.find("line 1: translation_m[2] puts the camera 2.5 m above "
                                      "the floor, at or above the ceiling of room 'low'"),
            std::string::npos)
      << high.error().message;
  const auto not_unit = ParseCameraMount(
      "translation_m: [0, 0, 0.3]\nrotation_xyzw: [0, 0, 0, 2]\n", "mount.pbtxt", map);
  ASSERT_FALSE(not_unit.ok());
  EXPECT_NE(not_unit.error().message.find("line 2: rotation_xyzw must be a unit quaternion"),
            std::string::npos)
      << not_unit.error().message;
  EXPECT_TRUE(
      ParseCameraMount("translation_m: [0, 0, 0.3]\nrotation_xyzw: [0, 0, 0, 1]\n", "m", map).ok());
}

}  // namespace
}  // namespace monocle

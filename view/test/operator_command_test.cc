// Tests that a page's operator request becomes the node's control command, and that a bad one is
// refused naming the field, with nothing to send.
#include <gtest/gtest.h>

#include "view/operator_command.h"

namespace dt {
namespace {

const std::set<std::string> kNodes = {"node-1", "node-2"};

TEST(OperatorCommand, EachOpBecomesTheNodesControlCommand) {
  auto c = ParseOperatorCommand(
      {{"op", "crater"}, {"node", "node-1"}, {"x", 300.5}, {"z", 400}, {"radius", 12}}, kNodes);
  ASSERT_TRUE(c.ok()) << c.error().message;
  EXPECT_EQ(c.value().node, "node-1");
  EXPECT_EQ(c.value().line, "crater 300.5 400 12");
  c = ParseOperatorCommand(
      {{"op", "breach"}, {"node", "node-2"}, {"id", "1:1:3"}, {"gap_start", 5}, {"gap_width", 4}},
      kNodes);
  ASSERT_TRUE(c.ok()) << c.error().message;
  EXPECT_EQ(c.value().line, "breach 1:1:3 5 4");
  c = ParseOperatorCommand({{"op", "destroy"}, {"node", "node-2"}, {"id", "1:2:7"}}, kNodes);
  ASSERT_TRUE(c.ok());
  EXPECT_EQ(c.value().line, "destroy 1:2:7");
  c = ParseOperatorCommand({{"op", "berm"},
                            {"node", "node-1"},
                            {"x", 1},
                            {"z", 2},
                            {"dir_deg", 90},
                            {"length", 40},
                            {"width", 4},
                            {"height", 2}},
                           kNodes);
  ASSERT_TRUE(c.ok());
  EXPECT_EQ(c.value().line, "berm 1 2 90 40 4 2");
}

TEST(OperatorCommand, ABadRequestIsRefusedNamingTheField) {
  auto c = ParseOperatorCommand({{"op", "crater"}, {"node", "server"}, {"x", 1}}, kNodes);
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.error().message.find("\"server\" is no node"), std::string::npos);
  c = ParseOperatorCommand({{"op", "crater"}, {"node", "node-1"}, {"x", 1}, {"z", "a"}}, kNodes);
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.error().message.find("\"z\""), std::string::npos);
  c = ParseOperatorCommand({{"op", "destroy"}, {"node", "node-1"}, {"id", "1:1; quit"}}, kNodes);
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.error().message.find("\"id\""), std::string::npos);
  c = ParseOperatorCommand({{"op", "quit"}, {"node", "node-1"}}, kNodes);
  ASSERT_FALSE(c.ok());
  EXPECT_NE(c.error().message.find("\"op\" \"quit\""), std::string::npos);
}

}  // namespace
}  // namespace dt

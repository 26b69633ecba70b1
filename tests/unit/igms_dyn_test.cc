// igms-dyn's JSON contract: info and eval on streams, with bad lines.
#include <gtest/gtest.h>

#include <nlohmann/json.hpp>
#include <sstream>

#include "core/model_io/model_loader.h"
#include "tests/support/test_models.h"
#include "tools/igms_dyn/commands.h"

namespace igms::test {
namespace {

using nlohmann::json;

std::vector<json> evalLines(const Model& m, const std::string& input, int* code) {
  std::istringstream in(input);
  std::ostringstream out, err;
  *code = dyn::eval(m, in, out, err);
  std::vector<json> lines;
  std::istringstream o(out.str());
  std::string line;
  while (std::getline(o, line)) lines.push_back(json::parse(line));
  return lines;
}

TEST(IgmsDyn, InfoListsJointsWithIndicesAndEveryLink) {
  BuildOptions fb;
  fb.floating_base = true;
  const Model m = loadModel(sourceDir() + "/models/quadruped.urdf", fb);
  std::ostringstream out;
  EXPECT_EQ(dyn::info(m, out), 0);
  const json j = json::parse(out.str());
  EXPECT_EQ(j["nq"], 19);
  EXPECT_EQ(j["nv"], 18);
  EXPECT_EQ(j["joints"][0]["type"], "floating");
  EXPECT_EQ(j["joints"][1]["q_index"], 7);
  EXPECT_EQ(j["joints"][1]["v_index"], 6);
  EXPECT_EQ(j["links"].size(), 1u + 1u + 4u * 4u);  // trunk, imu, 4 x (hip thigh calf foot)
}

TEST(IgmsDyn, InfoNamesEachJointType) {
  const std::string xml =
      "<robot name=\"t\"><link name=\"a\"/><link name=\"b\"><inertial><mass value=\"1\"/><inertia ixx=\"1\" "
      "ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial></link><link name=\"c\"><inertial><mass "
      "value=\"1\"/><inertia ixx=\"1\" ixy=\"0\" ixz=\"0\" iyy=\"1\" iyz=\"0\" izz=\"1\"/></inertial></link>"
      "<joint name=\"ab\" type=\"continuous\"><parent link=\"a\"/><child link=\"b\"/></joint>"
      "<joint name=\"bc\" type=\"prismatic\"><parent link=\"b\"/><child link=\"c\"/><limit lower=\"0\" "
      "upper=\"1\" effort=\"1\" velocity=\"1\"/></joint></robot>";
  std::ostringstream out;
  dyn::info(modelFromUrdf(xml), out);
  const json j = json::parse(out.str());
  EXPECT_EQ(j["joints"][0]["type"], "continuous");
  EXPECT_EQ(j["joints"][1]["type"], "prismatic");
}

TEST(IgmsDyn, EvalGivesTauMBiasQddAndPoses) {
  const Model m = loadModel(sourceDir() + "/models/puma560.urdf");
  int code = -1;
  const auto out = evalLines(
      m, R"({"q":[0.1,0.2,0.3,0.4,0.5,0.6],"v":[1,0,0,0,0,0],"a":[0,1,0,0,0,0],"tau":[0,0,0,0,0,0]})", &code);
  ASSERT_EQ(out.size(), 1u);
  EXPECT_EQ(code, 0);
  for (const char* k : {"tau", "M", "bias", "qdd", "poses"}) EXPECT_TRUE(out[0].contains(k)) << k;
  // tau = M a + bias with a = e_1.
  for (int i = 0; i < 6; ++i)
    EXPECT_NEAR(out[0]["tau"][i].get<double>(), out[0]["M"][i][1].get<double>() + out[0]["bias"][i].get<double>(),
                1e-12);
  EXPECT_EQ(out[0]["poses"].size(), m.frames.size());
  EXPECT_EQ(out[0]["poses"]["ee_link"].size(), 7u);
  EXPECT_GE(out[0]["poses"]["ee_link"][3].get<double>(), 0.0);  // w >= 0
}

TEST(IgmsDyn, ExternalForceAtTheBaseOfALinkActsThroughJacobianTranspose) {
  const Model m = loadModel(sourceDir() + "/models/puma560.urdf");
  int code = -1;
  const std::string q = R"("q":[0,0,0,0,0,0],"v":[0,0,0,0,0,0],"a":[0,0,0,0,0,0])";
  const auto out = evalLines(m,
                             "{" + q + "}\n{" + q +
                                 R"(,"fext":[{"link":"link1","point":[0.5,0,0],"force":[0,10,0]}]})",
                             &code);
  ASSERT_EQ(out.size(), 2u);
  // link1's frame is at the world origin at q = 0; a +y force at (0.5, 0, 0)
  // in link1's frame, which is rotated pi/2 about x: the point is at (0.5, 0, 0)
  // in the world, the moment about z is 0.5 * 10 = 5 N m, resisted by tau_1 = -5.
  EXPECT_NEAR(out[1]["tau"][0].get<double>() - out[0]["tau"][0].get<double>(), -5.0, 1e-12);
}

TEST(IgmsDyn, BadLinesGiveErrorLinesAndTheRestStillRuns) {
  const Model m = loadModel(sourceDir() + "/models/puma560.urdf");
  int code = -1;
  const std::string good = R"({"q":[0,0,0,0,0,0],"v":[0,0,0,0,0,0]})";
  const auto out = evalLines(m,
                             "not json\n" + good + "\n" + R"({"q":[0,0,0],"v":[0,0,0,0,0,0]})" + "\n" +
                                 R"({"q":[0,0,0,0,0,NaN],"v":[0,0,0,0,0,0]})" + "\n" +
                                 R"({"q":[0,0,0,0,0,0],"v":[0,0,0,0,0,0],"a":[0,0,0,0,0,0],"fext":[{"link":"ghost","point":[0,0,0],"force":[1,0,0]}]})" +
                                 "\n" + R"({"q":[0,0,0,0,0,0],"v":[0,0,0,0,0,"x"]})" + "\n" + good + "\n",
                             &code);
  ASSERT_EQ(out.size(), 7u);
  EXPECT_EQ(code, 1);
  EXPECT_TRUE(out[0].contains("error"));
  EXPECT_NE(out[0]["error"].get<std::string>().find("line 1"), std::string::npos);
  EXPECT_TRUE(out[1].contains("M"));
  EXPECT_NE(out[2]["error"].get<std::string>().find("\"q\" has 3 entries, expected 6"), std::string::npos);
  EXPECT_TRUE(out[3].contains("error"));
  EXPECT_NE(out[4]["error"].get<std::string>().find("unknown link 'ghost'"), std::string::npos);
  EXPECT_NE(out[5]["error"].get<std::string>().find("\"v\"[5] is not a number"), std::string::npos);
  EXPECT_TRUE(out[6].contains("M"));
}

TEST(IgmsDyn, FloatingBaseTauStartsWithTheBaseWrench) {
  BuildOptions fb;
  fb.floating_base = true;
  const Model m = loadModel(sourceDir() + "/models/quadruped.urdf", fb);
  int code = -1;
  // At rest with identity orientation and zero acceleration, the base wrench
  // holds the whole robot against gravity: force +m g along z.
  std::string q = "[0,0,0,1,0,0,0";
  for (int i = 0; i < 12; ++i) q += ",0";
  std::string z = "[0";
  for (int i = 1; i < 18; ++i) z += ",0";
  const auto out = evalLines(m, "{\"q\":" + q + "],\"v\":" + z + "],\"a\":" + z + "]}", &code);
  ASSERT_EQ(code, 0);
  EXPECT_NEAR(out[0]["tau"][2].get<double>(), m.totalMass() * 9.81, 1e-9);
  EXPECT_NEAR(out[0]["tau"][0].get<double>(), 0.0, 1e-12);
  EXPECT_EQ(out[0]["M"].size(), 18u);
}

}  // namespace
}  // namespace igms::test

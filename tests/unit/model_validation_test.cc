// Bad models get a clear error naming the file and the element; odd but valid
// data (massless links, point masses, broken triangle inequality) loads.
#include <gtest/gtest.h>

#include "core/dynamics/aba.h"
#include "core/dynamics/forward_dynamics.h"
#include "core/model_io/dh_loader.h"
#include "core/model_io/model_loader.h"
#include "tests/support/test_models.h"

namespace igms::test {
namespace {

const char* kLink = "<link name=\"%s\"><inertial><mass value=\"1\"/><inertia ixx=\"0.1\" ixy=\"0\" ixz=\"0\" "
                    "iyy=\"0.1\" iyz=\"0\" izz=\"0.1\"/></inertial></link>";

std::string link(const std::string& name) {
  std::string s = kLink;
  return s.replace(s.find("%s"), 2, name);
}

std::string joint(const std::string& name, const std::string& parent, const std::string& child,
                  const std::string& type = "revolute") {
  return "<joint name=\"" + name + "\" type=\"" + type + "\"><parent link=\"" + parent + "\"/><child link=\"" + child +
         "\"/><axis xyz=\"0 0 1\"/><limit lower=\"-1\" upper=\"1\" effort=\"1\" velocity=\"1\"/></joint>";
}

std::string robot(const std::string& body) { return "<robot name=\"r\">" + body + "</robot>"; }

// The ModelError message, or "" if the model built.
std::string errorOf(const std::string& xml) {
  try {
    buildModel(parseUrdfDescription(xml, "bad.urdf"), {});
  } catch (const ModelError& e) {
    return e.what();
  }
  return "";
}

TEST(ModelValidation, MalformedXmlNamesTheFile) {
  const std::string e = errorOf("<robot name=\"r\"><link name=\"a\"></robot");
  EXPECT_NE(e.find("bad.urdf"), std::string::npos) << e;
}

TEST(ModelValidation, MissingFileNamesTheFile) {
  try {
    loadModel("/nonexistent/robot.urdf");
    FAIL() << "no error";
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("/nonexistent/robot.urdf: cannot open"), std::string::npos) << e.what();
  }
}

TEST(ModelValidation, UnknownParentLinkIsRejected) {
  const std::string e = errorOf(robot(link("a") + link("b") + joint("j", "ghost", "b")));
  EXPECT_NE(e.find("bad.urdf"), std::string::npos);
  EXPECT_FALSE(e.empty());
}

TEST(ModelValidation, CycleIsRejected) {
  // urdfdom rejects a link with two parents; a cycle without any root is
  // caught by the builder. Both name the file.
  EXPECT_NE(errorOf(robot(link("a") + link("b") + link("c") + joint("j1", "a", "b") + joint("j2", "b", "c") +
                          joint("j3", "c", "b")))
                .find("bad.urdf"),
            std::string::npos);
  RobotDescription d;
  d.source = "cycle.urdf";
  d.links.resize(2);
  d.links[0].name = "a";
  d.links[1].name = "b";
  JointDescription j1, j2;
  j1.name = "j1"; j1.parent = "a"; j1.child = "b";
  j2.name = "j2"; j2.parent = "b"; j2.child = "a";
  d.joints = {j1, j2};
  try {
    buildModel(d, {});
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("cycle.urdf: no root link: the joints form a cycle"), std::string::npos)
        << e.what();
  }
}

TEST(ModelValidation, NegativeMassIsRejectedWithTheLinkName) {
  std::string bad = link("b");
  bad.replace(bad.find("value=\"1\""), 9, "value=\"-2\"");
  const std::string e = errorOf(robot(link("a") + bad + joint("j", "a", "b")));
  EXPECT_NE(e.find("bad.urdf: link 'b': mass is negative"), std::string::npos) << e;
}

TEST(ModelValidation, UnreadableInertialIsRejectedNotDropped) {
  // urdfdom alone would drop this <inertial> and leave 'b' massless.
  std::string bad = link("b");
  bad.replace(bad.find("ixx=\"0.1\""), 9, "ixx=\"nan\"");
  const std::string e = errorOf(robot(link("a") + bad + joint("j", "a", "b")));
  EXPECT_NE(e.find("bad.urdf: "), std::string::npos) << e;
  EXPECT_NE(e.find("Could not parse inertial element for Link [b]"), std::string::npos) << e;
}

TEST(ModelValidation, NonFiniteInertiaIsRejected) {
  try {
    parseDhDescription("links:\n  - {a: 0, alpha: 0, d: 0, mass: 1, inertia: [.nan, 0.1, 0.1, 0, 0, 0]}\n", "nan.yaml");
    buildModel(parseDhDescription("links:\n  - {a: 0, alpha: 0, d: 0, mass: 1, inertia: [.nan, 0.1, 0.1, 0, 0, 0]}\n",
                                  "nan.yaml"), {});
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("nan.yaml: link 'link1': inertia is not finite"), std::string::npos) << e.what();
  }
}

TEST(ModelValidation, IndefiniteInertiaIsRejected) {
  std::string bad = link("b");
  bad.replace(bad.find("ixy=\"0\""), 7, "ixy=\"0.5\"");
  const std::string e = errorOf(robot(link("a") + bad + joint("j", "a", "b")));
  EXPECT_NE(e.find("link 'b': inertia is not positive semi-definite"), std::string::npos) << e;
}

TEST(ModelValidation, DuplicateLinkNameIsRejected) {
  const std::string e = errorOf(robot(link("a") + link("b") + link("b") + joint("j", "a", "b")));
  EXPECT_NE(e.find("bad.urdf"), std::string::npos);
  EXPECT_FALSE(e.empty());
}

TEST(ModelValidation, FloatingJointInsideTheTreeIsRejected) {
  const std::string e = errorOf(robot(link("a") + link("b") + joint("j", "a", "b", "floating")));
  EXPECT_NE(e.find("joint 'j': joint type 'floating' is not supported"), std::string::npos) << e;
}

TEST(ModelValidation, MassAndInertiaOddButValidDataLoadsWithWarnings) {
  // A link without <inertial> mid-chain, a point mass (zero inertia), a link
  // whose principal moments break the triangle inequality.
  const std::string xml = robot(
      "<link name=\"a\"/><link name=\"m\"/>" + link("p") +
      "<link name=\"t\"><inertial><mass value=\"1\"/><inertia ixx=\"0.01\" ixy=\"0\" ixz=\"0\" iyy=\"0.01\" "
      "iyz=\"0\" izz=\"0.5\"/></inertial></link>" +
      joint("j1", "a", "m") + joint("j2", "m", "p") + joint("j3", "p", "t"));
  std::vector<std::string> warnings;
  const Model m = buildModel(parseUrdfDescription(xml, "odd.urdf"), {}, &warnings);
  EXPECT_EQ(m.nv, 3);
  bool triangle = false;
  for (const auto& w : warnings) triangle |= w.find("link 't'") != std::string::npos && w.find("triangle") != std::string::npos;
  EXPECT_TRUE(triangle);
}

TEST(ModelValidation, MasslessSubtreeMakesForwardDynamicsFailByName) {
  const std::string xml = robot(link("a") + link("b") + "<link name=\"empty\"/>" + joint("j1", "a", "b") +
                                joint("j_empty", "b", "empty"));
  std::vector<std::string> warnings;
  const Model m = buildModel(parseUrdfDescription(xml, "massless.urdf"), {}, &warnings);
  bool warned = false;
  for (const auto& w : warnings) warned |= w.find("joint 'j_empty'") != std::string::npos;
  EXPECT_TRUE(warned);
  Data d(m);
  EXPECT_FALSE(forwardDynamics(m, d, VectorX::Zero(2), VectorX::Zero(2), VectorX::Ones(2)));
  EXPECT_EQ(dofName(m, d.singular_dof), "j_empty");
  EXPECT_FALSE(aba(m, d, VectorX::Zero(2), VectorX::Zero(2), VectorX::Ones(2)));
  EXPECT_EQ(dofName(m, d.singular_dof), "j_empty");
}

TEST(ModelValidation, FixedJointsAreMergedAndKeepEveryLinkAsAFrame) {
  const std::string xml = robot(link("a") + link("b") + link("c") + link("d") + joint("j1", "a", "b") +
                                joint("fixed_bc", "b", "c", "fixed") + joint("j2", "c", "d"));
  const Model m = modelFromUrdf(xml);
  EXPECT_EQ(m.nb, 2);
  EXPECT_EQ(m.frames.size(), 4u);
  EXPECT_DOUBLE_EQ(m.inertia[0].m, 2.0);  // b and c merged
  EXPECT_EQ(m.frame(m.frameIndex("c")).body, m.frame(m.frameIndex("b")).body);
}

TEST(ModelValidation, DhErrorsNameFileLineAndKey) {
  try {
    parseDhDescription("name: x\nlinks:\n  - {joint: j1, alpha: 0, d: 0}\n", "arm.dh.yaml");
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("arm.dh.yaml:3: missing key 'a'"), std::string::npos) << e.what();
  }
  try {
    parseDhDescription("links:\n  - {a: 0, alpha: x, d: 0}\n", "arm.dh.yaml");
    FAIL();
  } catch (const ModelError& e) {
    EXPECT_NE(std::string(e.what()).find("key 'alpha': not a number"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace igms::test

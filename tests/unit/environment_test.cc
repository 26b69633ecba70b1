// The scene as an environment: several robots and free bodies in one model
// (their names, coordinates and controllers), the scene's errors for the new
// keys, contact pairs' rules, and a step that allocates nothing with contact.
#include <gtest/gtest.h>

#include "core/contact/contact_model.h"
#include "core/dynamics/crba.h"
#include "core/dynamics/ltdl.h"
#include "core/geometry/shape_bounds.h"
#include "core/geometry/shape_inertia.h"
#include "core/geometry/shape_kind.h"
#include "core/model/environment_model.h"
#include "core/model/frame_names.h"
#include "core/simulation/coupled_dynamics.h"
#include "core/simulation/simulation.h"
#include "tests/support/malloc_counter.h"
#include "tests/support/test_models.h"

namespace igms {
namespace {

Scene shipped(const char* name) { return loadScene(test::sourceDir() + "/scenes/" + name); }

std::string error(const std::string& yaml) {
  try {
    resolveScene(parseScene(yaml, "bad.yaml", test::sourceDir() + "/scenes"));
  } catch (const std::exception& e) {
    return e.what();
  }
  return "";
}

TEST(Environment, SeveralRobotsAndFreeBodiesAreTreesOfOneModel) {
  const ResolvedScene r = resolveScene(shipped("workcell.yaml"));
  const Model& m = *r.model;
  ASSERT_EQ(m.parts.size(), 5u);
  EXPECT_EQ(m.parts[0].name, "puma");
  EXPECT_EQ(m.parts[1].name, "go1");
  EXPECT_TRUE(m.parts[2].free_body);
  EXPECT_GE(m.frameIndex("puma/ee_link"), 0) << "a robot's links named ROBOT/link";
  EXPECT_GE(m.frameIndex("go1/trunk"), 0);
  EXPECT_GE(m.frameIndex("ball"), 0);
  EXPECT_EQ(m.partOfFrame(m.frameIndex("go1/trunk")), 1);
  // No coordinate, dof or body crosses from one tree to another.
  for (const ModelPart& p : m.parts)
    for (int k = p.dof_begin; k < p.dof_end; ++k) EXPECT_TRUE(m.dof_parent[k] < 0 || m.dof_parent[k] >= p.dof_begin);
  // The initial state: each robot's q where it belongs, each free body at its pose.
  EXPECT_DOUBLE_EQ(r.q0[m.parts[0].q_begin], -0.9);
  EXPECT_DOUBLE_EQ(r.q0[m.parts[1].q_begin], -0.8);
  EXPECT_DOUBLE_EQ(r.q0[m.parts[4].q_begin + 2], 0.16);
  const std::vector<std::string> names = coordinateNames(m);
  EXPECT_EQ(names[0], "puma.q0");
  EXPECT_EQ(names[static_cast<size_t>(m.parts[4].q_begin + 3)], "ball.qw");
  // Each robot follows its own controller: the PUMA its line, the Go1 its posture.
  Simulation sim(r);
  for (int k = 0; k < 4500; ++k) ASSERT_TRUE(sim.step(nullptr));
  const Vector3 ee = sim.linkPoses()[static_cast<size_t>(m.frameIndex("puma/ee_link"))].p;
  EXPECT_LT((ee - Vector3(0.45, 0.47, 0.25)).norm(), 0.01) << "the PUMA reached its target";
  EXPECT_NEAR(sim.q()[m.parts[1].q_begin + 2], -0.124, 0.01) << "the Go1 stands where it was put";
}

TEST(Environment, EachRobotRecordsItsOwnEditedMotion) {
  Simulation workcell(shipped("workcell.yaml"));
  for (int k = 0; k < 50; ++k) ASSERT_TRUE(workcell.step(nullptr));
  ASSERT_EQ(workcell.robots(), 2);
  const EditedTrajectory& puma = workcell.robot(0).edited();
  ASSERT_GE(puma.count(), 2);
  EXPECT_EQ(puma.point(1).size(), workcell.model().parts[0].nq()) << "the PUMA's 6, not every body's pose";
  EXPECT_DOUBLE_EQ(puma.point(0)[0], -0.9);
  const EditedTrajectory& go1 = workcell.robot(1).edited();
  ASSERT_EQ(go1.count(), puma.count());
  const ModelPart& legs = workcell.model().parts[1];
  EXPECT_EQ(go1.point(1).size(), legs.nq()) << "the Go1's own coordinates";
  EXPECT_EQ(VectorX(go1.point(go1.count() - 1)), VectorX(workcell.q().segment(legs.q_begin, legs.nq())))
      << "its last sample is where it stands now";
  // A scene of free bodies alone records nothing (10 minutes of a pile's poses would be 725 MB)
  // and says so when asked to save it.
  Simulation pile(shipped("sphere_pile.yaml"));
  for (int k = 0; k < 50; ++k) ASSERT_TRUE(pile.step(nullptr));
  EXPECT_EQ(pile.robots(), 0);
  try {
    pile.saveEdited(0, "/tmp/igms_environment_test_pile.yaml");
    ADD_FAILURE() << "saved a robot's motion from a scene without a robot";
  } catch (const std::runtime_error& e) {
    EXPECT_NE(std::string(e.what()).find("no robot"), std::string::npos) << e.what();
  }
}

TEST(Environment, OneRobotAloneKeepsItsModelAsItWas) {
  const ResolvedScene alone = resolveScene(shipped("puma_wall.yaml"));
  ASSERT_EQ(alone.model->parts.size(), 1u);
  EXPECT_EQ(alone.model->frames[0].name, "base_link") << "no prefix";
  Simulation sim(alone);
  EXPECT_FALSE(sim.hasContacts()) << "no pair can touch: no contact step";
}

TEST(Environment, ErrorsNameTheFileAndTheKey) {
  const std::pair<const char*, const char*> cases[] = {  // a scene, what its error says
      {"bodies: [{name: b, shape: cone, radius: 1}]\n",
       "bad.yaml:1: bodies[0].shape: must be box, cylinder, sphere, capsule or mesh"},
      {"bodies: [{name: b, shape: sphere, radius: 0.1, material: steel}]\n",
       "bodies[0].material: unknown material 'steel' (the scene's: default)"},
      {"bodies: [{name: b, shape: sphere, radius: 0.1, mass: 1, density: 3}]\n",
       "bodies[0].density: give mass or density, not both"},
      {"bodies: [{name: b, shape: sphere, radius: 0.1}, {name: b, shape: sphere, radius: 0.1}]\n",
       "another body is named 'b'"},
      {"robots: [{model: ../models/puma560.urdf}]\ninitial: {q: [0]}\n", "initial: belongs to a robot"},
      {"materials: {m: {restitution: 2}}\nbodies: [{shape: sphere, radius: 0.1}]\n",
       "materials.m.restitution: must be in [0, 1]"},
      {"materials: {m: {rolling: -0.001}}\nbodies: [{shape: sphere, radius: 0.1}]\n",
       "materials.m.rolling: must be >= 0 (m)"},
      {"materials: {m: {torsion: .nan}}\nbodies: [{shape: sphere, radius: 0.1}]\n", "torsion: not finite"},
      {"materials: {m: {rollin: 0.1}}\nbodies: [{shape: sphere, radius: 0.1}]\n", "rollin"},
      {"ground: true\nbodies: [{shape: sphere, radius: 0.1}]\nsimulation: {integrator: rk4}\n", "rk4 cannot take contact"},
      {"robot: {model: ../models/puma560.urdf}\nbodies: [{name: link1, shape: sphere, radius: 0.1}]\n",
       "two links are named 'link1'"},
      {"bodies: [{name: m, shape: mesh, file: nowhere.stl}]\n", "bodies[0].file"},
  };
  for (const auto& [yaml, expected] : cases) EXPECT_NE(error(yaml).find(expected), std::string::npos) << yaml;
}

// A shape kind is a row of core/geometry/shape_kind's table: the scene reads each primitive by the
// table's keys alone, and the geometry layer bounds it and gives its mass.
TEST(Environment, EveryPrimitiveKindIsReadByItsRowOfTheTable) {
  int k = 0;
  for (const ShapeKindInfo& kind : shapeKinds()) {
    EXPECT_EQ(static_cast<int>(kind.kind), k++) << kind.name << ": the table is in the enum's order";
    EXPECT_EQ(shapeKindNamed(kind.name), &kind);
    if (!kind.primitive) continue;
    // The body in YAML with each of the kind's numbers but `skip`'s, distinct values from 0.07 m on.
    Vector3 size = Vector3::Zero();
    const auto yaml = [&](const char* skip) {
      std::string y = std::string("bodies: [{name: b, shape: ") + kind.name;
      double x = 0.07;
      for (const ShapeDimension& d : kind.dimensions) {
        if (!d.key || d.key == skip) continue;
        y += std::string(", ") + d.key + ": " + (d.count > 1 ? "[" : "");
        for (int i = 0; i < d.count; ++i, x += 0.03) {
          y += (i ? ", " : "") + std::to_string(x);
          size[d.at + i] = x;
        }
        y += d.count > 1 ? "]" : "";
      }
      return y + ", mass: 1}]\n";
    };
    const std::string whole = yaml(nullptr);
    const ResolvedScene r = resolveScene(parseScene(whole, "kinds.yaml", test::sourceDir() + "/scenes"));
    ASSERT_EQ(r.model->frames.size(), 1u) << whole;
    const CollisionShape& shape = r.model->frames[0].collisions.at(0);
    EXPECT_EQ(shape.kind, kind.kind) << whole;
    EXPECT_TRUE(shape.size.isApprox(size, 1e-12)) << whole << shape.size.transpose();
    EXPECT_GT(boundingRadius(shape), 0.0) << kind.name;
    EXPECT_GT(shapeMassProperties(shape).volume, 0.0) << kind.name;
    // Each of the kind's numbers is required: a shape without one is refused, naming it.
    for (const ShapeDimension& d : kind.dimensions) {
      if (d.key) {
        EXPECT_NE(error(yaml(d.key)).find(std::string("bodies[0].") + d.key), std::string::npos)
            << kind.name << " without " << d.key << ": " << error(yaml(d.key));
      }
    }
  }
}

TEST(Environment, FreeBodiesTakeTheirInertiaFromTheirShape) {
  const ResolvedScene r = resolveScene(parseScene(
      "bodies:\n  - {name: b, shape: box, size: [0.1, 0.2, 0.3], density: 1000}\n"
      "  - {name: c, shape: capsule, radius: 0.05, length: 0.2, mass: 2}\n"
      "  - {name: u, shape: mesh, file: ../models/meshes/u_channel.obj, density: 500}\n",
      "t.yaml", test::sourceDir() + "/scenes"));
  const Model& m = *r.model;
  EXPECT_NEAR(m.inertia[0].m, 6.0, 1e-12);
  EXPECT_NEAR(m.inertia[0].Io(0, 0), 6.0 / 12.0 * (0.04 + 0.09), 1e-12);
  EXPECT_NEAR(m.inertia[1].m, 2.0, 1e-12);
  // The channel: 0.009 m^3 of a non-convex solid, by the divergence theorem (assimp reads the
  // vertices as floats: 1e-7 relative).
  EXPECT_NEAR(m.inertia[2].m, 500.0 * 0.009, 1e-6 * 4.5);
}

TEST(Environment, ARobotsOwnLinksTouchOnlyWhenAskedAndNeverNextToEachOther) {
  const ResolvedScene r = resolveScene(shipped("go1_stand.yaml"));
  const GeometryModel robot(*r.model, r.part_material, {});  // the robot's links alone: no ground
  const ContactModel off(*r.model, robot, {Material{}}, ContactSettings{});
  ContactSettings on;
  on.self_collision = true;
  const ContactModel self(*r.model, robot, {Material{}}, on);
  const Model& m = *r.model;
  int pairs_off = 0, pairs_on = 0, adjacent = 0;
  const auto& g = robot.objects();
  for (int i = 0; i < static_cast<int>(g.size()); ++i)
    for (int j = i + 1; j < static_cast<int>(g.size()); ++j) {
      pairs_off += off.canTouch(i, j);
      pairs_on += self.canTouch(i, j);
      const int a = g[static_cast<size_t>(i)].body, b = g[static_cast<size_t>(j)].body;
      if (a >= 0 && b >= 0 && (m.parent[static_cast<size_t>(a)] == b || m.parent[static_cast<size_t>(b)] == a))
        adjacent += self.canTouch(i, j);
    }
  EXPECT_EQ(pairs_off, 0);
  EXPECT_GT(pairs_on, 0);
  EXPECT_EQ(adjacent, 0);
}

TEST(Environment, TheStepAllocatesNothingWithContact) {
  // ball_on_mesh: meshes (their hierarchy beyond the field's band), free bodies flying (their own step) and landing.
  // sphere_pile: 217 geoms, the broad phase's grid (broad_phase.h), and pairs waiting without rows.
  for (const char* name :
       {"go1_stand.yaml", "puma_table.yaml", "box_tower.yaml", "workcell.yaml", "ball_on_mesh.yaml", "sphere_pile.yaml"}) {
    Simulation sim(shipped(name));
    for (int k = 0; k < 20; ++k) ASSERT_TRUE(sim.step(nullptr));  // warm
    InteractionInput push;
    push.mode = InteractionMode::Push;
    push.tip_position = sim.linkPoses()[1].p;
    push.client = 1;
    const size_t n = test::allocationsDuring([&] {
      for (int k = 0; k < 200; ++k) sim.step(nullptr);
      for (int k = 0; k < 50; ++k) {
        push.seq = k;
        sim.step(&push);
      }
      for (int k = 0; k < 50; ++k) sim.step(nullptr);
    });
    EXPECT_EQ(n, 0u) << name;
    EXPECT_GT(sim.contacts().n, 0) << name;
  }
}

TEST(Environment, TheStepAllocatesNothingSolvingALargeIsland) {
  // ball_lattice: one island of 1,728 unknowns, solved by conjugate gradients in its first step
  // (contact_active_set.h); after a reset, again.
  Simulation sim(shipped("ball_lattice.yaml"));
  for (int k = 0; k < 20; ++k) ASSERT_TRUE(sim.step(nullptr));  // warm
  sim.reset();
  const int64_t before = sim.contactStats().large_solves;
  const size_t n = test::allocationsDuring([&] {
    for (int k = 0; k < 20; ++k) sim.step(nullptr);
  });
  EXPECT_EQ(n, 0u);
  EXPECT_GT(sim.contactStats().large_solves, before) << "the window took conjugate gradients";
}

TEST(Environment, TheStepAllocatesNothingWhileSlipsAreTurned) {
  // puma_table's arm shoving its boxes for 8 s: thousands of active-set answers whose slipping
  // friction Newton's method turns against its slip (contact_active_set.h), a few it cannot, and the
  // islands the active set cannot settle, answered on the linearised cone (Lemke's method).
  Simulation sim(shipped("puma_table.yaml"));
  for (int k = 0; k < 20; ++k) ASSERT_TRUE(sim.step(nullptr));  // warm
  const int64_t unturned = sim.contactStats().slips_unturned;
  const int64_t linearised = sim.contactStats().linearised_exact + sim.contactStats().linearised;
  const size_t n = test::allocationsDuring([&] {
    for (int k = 0; k < 7980; ++k) sim.step(nullptr);
  });
  EXPECT_EQ(n, 0u);
  EXPECT_GT(sim.contactStats().slips_unturned, unturned) << "an answer kept its slip unturned within the steps";
  EXPECT_GT(sim.contactStats().linearised_exact + sim.contactStats().linearised, linearised + 10)
      << "islands on the linearised cone within the steps (53 measured)";
}

TEST(Environment, TheStepAllocatesNothingThroughEveryPolytope) {
  // puma_table with box_a moved 111 nm: at step 2438 an island no seed of any of the three polytopes
  // settles (ContactActiveSet::kPolytopes), so each polytope's LCP is built, solved and seeded.
  Scene scene = shipped("puma_table.yaml");
  scene.bodies.at(0).pose.p.x() += 111e-9;
  Simulation sim(scene);
  for (int k = 0; k < 20; ++k) ASSERT_TRUE(sim.step(nullptr));  // warm
  const size_t n = test::allocationsDuring([&] {
    for (int k = 0; k < 2580; ++k) sim.step(nullptr);
  });
  EXPECT_EQ(n, 0u);
  EXPECT_GE(sim.contactStats().linearised, 1) << "an island kept a polytope's answer (step 2438)";
}

TEST(Environment, TheStepAllocatesNothingSharingOpposedOverlaps) {
  // A peg 0.4 mm wider than the U channel's slot: both walls overlap it, and the position correction
  // shares their overlap (contact_solver.cc) on the steps measured.
  Simulation sim(parseScene(
      "materials: {m: {friction: 0.5}}\n"
      "obstacles: [{name: u, shape: mesh, file: ../models/meshes/u_channel.obj, solid: true, material: m}]\n"
      "bodies: [{name: peg, shape: box, size: [0.1004, 0.06, 0.06], mass: 0.5, xyz: [0, 0, 0.05], material: m}]\n",
      "peg.yaml", test::sourceDir() + "/scenes"));
  for (int k = 0; k < 20; ++k) ASSERT_TRUE(sim.step(nullptr));  // warm
  int opposed = 0;  // steps with two overlapping points whose normals oppose
  const size_t n = test::allocationsDuring([&] {
    for (int k = 0; k < 300; ++k) {
      sim.step(nullptr);
      const ContactSet& c = sim.contacts();
      bool found = false;
      for (int i = 0; i < c.n; ++i)
        for (int j = i + 1; j < c.n; ++j)
          found = found || (c[i].distance < -1e-6 && c[j].distance < -1e-6 && c[i].normal.dot(c[j].normal) < -0.9);
      opposed += found;
    }
  });
  EXPECT_EQ(n, 0u);
  EXPECT_GT(opposed, 0) << "the walls' overlaps were shared within the steps measured";
}

TEST(Environment, TheStepAllocatesNothingThroughChainedImpactsAndResistance) {
  // Three balls on a floor, the first rolling into the others at 0.1 m/s (its blow passed along the
  // row, contact_impacts.h), each with rolling and torsional resistance (three more rows a point).
  Simulation sim(parseScene(
      "ground: {height: 0, material: floor}\n"
      "materials: {steel: {friction: 0.2, restitution: 1.0, rolling: 0.001, torsion: 0.001}, "
      "floor: {friction: 0.5, rolling: 0.002, torsion: 0.001}}\n"
      "bodies:\n"
      "  - {name: a, shape: sphere, radius: 0.05, mass: 1, xyz: [-0.105, 0, 0.05], v: [0.1, 0, 0], w: [0, 2, 3], "
      "material: steel}\n"
      "  - {name: b, shape: sphere, radius: 0.05, mass: 1, xyz: [0, 0, 0.05], material: steel}\n"
      "  - {name: c, shape: sphere, radius: 0.05, mass: 1, xyz: [0.1, 0, 0.05], material: steel}\n",
      "chain.yaml", test::sourceDir() + "/scenes"));
  for (int k = 0; k < 20; ++k) ASSERT_TRUE(sim.step(nullptr));  // warm
  int passed = 0;
  const size_t n = test::allocationsDuring([&] {
    for (int k = 0; k < 200; ++k) {
      sim.step(nullptr);
      passed += sim.contactStats().impact_rounds > 0;
    }
  });
  EXPECT_EQ(n, 0u);
  EXPECT_GT(passed, 0) << "the blow was passed along within the steps measured";
}

TEST(Environment, AStepWithoutContactsReportsNoSolve) {
  // A ball bouncing on the floor (e = 1): each step it is clear of the floor, the last solve's figures
  // must not stand as the step's (the CSV, the server's status and Python read them per step).
  Simulation sim(parseScene(
      "ground: {height: 0, material: floor}\n"
      "materials: {steel: {friction: 0.5, restitution: 1.0}, floor: {friction: 0.5}}\n"
      "bodies:\n"
      "  - {name: ball, shape: sphere, radius: 0.05, mass: 1, xyz: [0, 0, 0.1], material: steel}\n",
      "bounce.yaml", test::sourceDir() + "/scenes"));
  int solved = 0, cleared = 0;
  bool touched = false;
  for (int k = 0; k < 1000; ++k) {
    ASSERT_TRUE(sim.step(nullptr));
    const ContactSolveStats& s = sim.contactStats();
    if (sim.contacts().n > 0) {
      solved += s.iterations > 0;
      touched = true;
      continue;
    }
    cleared += touched;
    touched = false;
    ASSERT_EQ(s.iterations, 0) << "step " << k;
    ASSERT_EQ(s.residual, 0.0) << "step " << k;
    ASSERT_EQ(s.polish_rounds, 0) << "step " << k;
    ASSERT_EQ(s.deferred, 0) << "step " << k;
    ASSERT_EQ(s.impact_rounds, 0) << "step " << k;
    ASSERT_EQ(s.position_sweeps, 0) << "step " << k;
    ASSERT_EQ(s.position_residual, 0.0) << "step " << k;
    ASSERT_EQ(s.slip_angle, 0.0) << "step " << k;
  }
  EXPECT_GT(solved, 0) << "the ball met the floor";
  EXPECT_GE(cleared, 2) << "and left it again";
}

TEST(Environment, TheSameSceneGivesTheSameBits) {
  Simulation a(shipped("puma_table.yaml")), b(shipped("puma_table.yaml"));
  for (int k = 0; k < 3000; ++k) {
    ASSERT_TRUE(a.step(nullptr));
    ASSERT_TRUE(b.step(nullptr));
  }
  for (int k = 0; k < a.q().size(); ++k) ASSERT_EQ(a.q()[k], b.q()[k]);
}

TEST(Environment, AFreeBodysFactorsAreFormedOnceAndAreThoseOfItsInertia) {
  // The implicit step's matrix: a free body's block that is its inertia alone comes back as its
  // factors (formed once), bit for bit what factoring it gives; a block with something added (the
  // hold's h c H) is left to be factored.
  Simulation sim(shipped("box_pyramid.yaml"));
  const Model& m = sim.model();
  CoupledDynamics dynamics(m, sim.scene(), sim.q());
  VectorX tau = VectorX::Zero(m.nv), v = VectorX::Constant(m.nv, 0.3), rhs(m.nv);
  CoupledInputs in{tau, nullptr, 0};
  CoupledEvaluation at = dynamics.makeEvaluation();
  TreeMatrix A(m);
  std::vector<char> factored(static_cast<size_t>(A.blocks()), 0);
  Data data(m);
  TreeMatrix want = crba(m, data, sim.q());
  ASSERT_LT(ltdlFactor(m.dof_parent, m.dof_run_start, want, data.diag), 0);
  dynamics.evaluate(in, sim.q(), v, at);
  dynamics.linearSystem(in, at, v, 1e-3, A, rhs, factored);
  int blocks = 0;
  for (int b = 0; b < A.blocks(); ++b) {
    ASSERT_TRUE(factored[static_cast<size_t>(b)]) << "block " << b << " (every one a free body)";
    ++blocks;
    for (int c = A.blockBegin(b); c < A.blockEnd(b); ++c)
      for (int r = A.blockBegin(b); r <= c; ++r) ASSERT_EQ(A(r, c), want(r, c)) << r << ", " << c;
  }
  EXPECT_EQ(blocks, 10);
  const std::vector<DofRange> everything{DofRange{0, m.nv, 5.0}};
  in.hold = &everything;  // A = H + h c H
  std::fill(factored.begin(), factored.end(), 0);
  dynamics.linearSystem(in, at, v, 1e-3, A, rhs, factored);
  for (int b = 0; b < A.blocks(); ++b) EXPECT_FALSE(factored[static_cast<size_t>(b)]) << "block " << b;
  EXPECT_DOUBLE_EQ(A(0, 0), (1.0 + 5e-3) * crba(m, data, sim.q())(0, 0));
}

// The bus edge resolves an input's link names once per session (FrameNames): every frame of a robot,
// of several robots with free bodies and of a 44-dof humanoid is found where Model::frameIndex finds
// it, an unknown name is -1, and a lookup allocates nothing.
TEST(FrameNames, FindEveryFrameWhereFrameIndexDoesWithoutAllocating) {
  for (const char* scene : {"puma_obstacle.yaml", "workcell.yaml", "talos_stand.yaml"}) {
    Simulation sim(loadScene(test::sourceDir() + "/scenes/" + scene));
    const Model& m = sim.model();
    const FrameNames names(m);
    for (const Frame& f : m.frames) EXPECT_EQ(names.find(f.name), m.frameIndex(f.name)) << scene << ": " << f.name;
    const std::string unknown[] = {"", "no_such_link", m.frames.back().name + "_", "\xff"};
    for (const std::string& u : unknown) EXPECT_EQ(names.find(u), -1) << scene;
    int sum = 0;
    const size_t allocations = test::allocationsDuring([&] {
      for (const Frame& f : m.frames) sum += names.find(f.name);
    });
    EXPECT_EQ(allocations, 0u) << scene;
    EXPECT_GT(sum, 0);
  }
}

}  // namespace
}  // namespace igms

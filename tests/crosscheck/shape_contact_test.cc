// The contact layer's geometry against independent answers, on random poses of
// every pair of box, cylinder, capsule and sphere:
//   apart: FCL 0.7's distance (its own GJK, libccd) — igms's GJK (convex_distance.h) within 1e-6 m;
//   overlapping: FCL's collide says they overlap, and the depth is the minimum over directions u of
//     the Minkowski support h_A(u) + h_B(-u): the separating axes (faces, edge-edge products), 200 000
//     sampled directions and a local descent from the best (FCL's own signed distance asserts inside
//     libccd's EPA on cylinders, and is off by centimetres where it does not) — igms's EPA within
//     1e-6 m of it;
// and the deepest point shapeContacts returns has those distances; points come out in a fixed order. Also the analytic cases that flat contacts rest on: a box on
// a plane has its four bottom corners, a standing cylinder four rim points, a
// capsule lying down its two ends, a box on a box four points.
#include <gtest/gtest.h>

#include <fcl/fcl.h>

#include <cmath>
#include <limits>
#include <memory>
#include <random>

#include "core/geometry/convex_distance.h"
#include "core/geometry/point_query.h"
#include "core/geometry/shape_contact.h"
#include "core/geometry/shape_kind.h"
#include "tests/support/malloc_counter.h"

namespace igms {
namespace {

using Kind = CollisionShape::Kind;

CollisionShape shape(Kind kind, double a, double b = 0.0, double c = 0.0) {
  CollisionShape s;
  s.kind = kind;
  s.size = Vector3(a, b, c);
  return s;
}

std::shared_ptr<fcl::CollisionGeometryd> fclShape(const CollisionShape& s) {
  switch (s.kind) {
    case Kind::Box: return std::make_shared<fcl::Boxd>(s.size[0], s.size[1], s.size[2]);
    case Kind::Cylinder: return std::make_shared<fcl::Cylinderd>(s.size[0], s.size[1]);
    case Kind::Sphere: return std::make_shared<fcl::Sphered>(s.size[0]);
    case Kind::Capsule: return std::make_shared<fcl::Capsuled>(s.size[0], s.size[1]);
    default: return nullptr;
  }
}

fcl::Transform3d toFcl(const SE3& M) {
  fcl::Transform3d T = fcl::Transform3d::Identity();
  T.linear() = M.R;
  T.translation() = M.p;
  return T;
}

// FCL's distance when the shapes are apart; when they overlap, minus the brute-force depth.
double referenceSignedDistance(const CollisionShape& a, const SE3& pa, const CollisionShape& b, const SE3& pb) {
  fcl::CollisionObjectd oa(fclShape(a), toFcl(pa)), ob(fclShape(b), toFcl(pb));
  fcl::CollisionRequestd crequest;
  fcl::CollisionResultd cresult;
  fcl::collide(&oa, &ob, crequest, cresult);
  if (!cresult.isCollision()) {
    fcl::DistanceRequestd request;
    request.gjk_solver_type = fcl::GST_LIBCCD;
    request.distance_tolerance = 1e-9;
    fcl::DistanceResultd result;
    fcl::distance(&oa, &ob, request, result);
    return result.min_distance;
  }
  ConvexShape ca, cb;
  convexOf(a, pa, &ca);
  convexOf(b, pb, &cb);
  static const std::vector<Vector3> directions = [] {
    std::vector<Vector3> u;
    std::mt19937 rng(99);
    std::normal_distribution<double> n;
    for (int k = 0; k < 200000; ++k) u.push_back(Vector3(n(rng), n(rng), n(rng)).normalized());
    return u;
  }();
  auto h = [&](const Vector3& u) { return u.dot(supportPoint(ca, u) - supportPoint(cb, -u)) + ca.radius + cb.radius; };
  // A polytope's minimum sits at a face normal or an edge-edge cross product (the separating axes),
  // where h rises linearly away from it: those directions exactly, then the sampled ones, then a
  // local descent from the best.
  std::vector<Vector3> axes;
  for (const ConvexShape* s : {&ca, &cb}) {
    if (s->core == ConvexShape::Core::Box)
      for (int k = 0; k < 3; ++k) axes.push_back(s->pose.R.col(k));
    if (s->core == ConvexShape::Core::Cylinder || s->core == ConvexShape::Core::Segment)
      axes.push_back(s->pose.R.col(2));
  }
  const size_t single = axes.size();
  for (size_t i = 0; i < single; ++i)
    for (size_t j = i + 1; j < single; ++j)
      if (axes[i].cross(axes[j]).norm() > 1e-9) axes.push_back(axes[i].cross(axes[j]).normalized());
  double depth = std::numeric_limits<double>::infinity();
  Vector3 best = Vector3::UnitZ();
  auto consider = [&](const Vector3& u) {
    const double d = h(u);
    if (d < depth) {
      depth = d;
      best = u;
    }
  };
  for (const Vector3& u : axes) {
    consider(u);
    consider(-u);
  }
  for (const Vector3& u : directions) consider(u);
  std::mt19937 rng(5);
  std::normal_distribution<double> n;
  for (double step = 1e-2; step > 1e-9; step *= 0.7)
    for (int k = 0; k < 200; ++k) consider((best + step * Vector3(n(rng), n(rng), n(rng))).normalized());
  return -depth;
}

SE3 randomPose(std::mt19937& rng, double spread) {
  std::uniform_real_distribution<double> u(-spread, spread);
  Eigen::Quaterniond q(std::normal_distribution<double>()(rng), std::normal_distribution<double>()(rng),
                       std::normal_distribution<double>()(rng), std::normal_distribution<double>()(rng));
  q.normalize();
  return SE3{q.toRotationMatrix(), Vector3(u(rng), u(rng), u(rng))};
}

std::vector<CollisionShape> primitives() {
  return {shape(Kind::Box, 0.3, 0.2, 0.1), shape(Kind::Cylinder, 0.08, 0.3), shape(Kind::Capsule, 0.05, 0.25),
          shape(Kind::Sphere, 0.1), shape(Kind::Box, 0.05, 0.4, 0.05), shape(Kind::Cylinder, 0.2, 0.04)};
}

TEST(ConvexDistance, AgreesWithFclOnRandomPairs) {
  std::mt19937 rng(7);
  int separated = 0, overlapping = 0;
  double worst_separated = 0.0, worst_overlap = 0.0;
  const auto shapes = primitives();
  for (size_t i = 0; i < shapes.size(); ++i)
    for (size_t j = 0; j < shapes.size(); ++j)
      for (int trial = 0; trial < 60; ++trial) {
        const SE3 pa = randomPose(rng, 0.05), pb = randomPose(rng, 0.25);
        ConvexShape ca, cb;
        ASSERT_TRUE(convexOf(shapes[i], pa, &ca));
        ASSERT_TRUE(convexOf(shapes[j], pb, &cb));
        const ConvexDistance d = convexDistance(ca, cb);
        ASSERT_TRUE(d.ok) << i << " " << j << " " << trial;
        const double truth = referenceSignedDistance(shapes[i], pa, shapes[j], pb);
        // The nearest points are on the surfaces and the normal points from a to b along them.
        EXPECT_NEAR(d.normal.norm(), 1.0, 1e-12);
        EXPECT_NEAR((d.on_b - d.on_a).dot(d.normal), d.distance, 1e-9);
        // Each side's answer is achieved by what it found (two surface points apart; a direction the
        // shapes overlap along), so the smaller is the nearer the truth: igms's may beat the
        // reference's by the reference's tolerance (libccd's GJK stops at about 1e-6 m; the descent
        // about as near), and lose to it by igms's rounding of box and cylinder edges (0.1 um, so that
        // faces that touch leave GJK something to measure) and, in overlaps, on curved cores (EPA's
        // polytope of at most 96 points approximates a deep overlap of two cylinders within microns).
        const auto kinds = std::string(shapeKindName(shapes[i].kind)) + "-" + shapeKindName(shapes[j].kind);
        if (truth > 1e-4) {
          ++separated;
          worst_separated = std::max(worst_separated, std::abs(d.distance - truth));
          // On a curved core GJK's nearest point is a chord's, inside the surface by its sagitta.
          EXPECT_NEAR(pointQuery(shapes[i], pa, d.on_a).distance, 0.0, 1e-4) << kinds;
          EXPECT_NEAR(pointQuery(shapes[j], pb, d.on_b).distance, 0.0, 1e-4) << kinds;
          EXPECT_LT(d.distance, truth + 2e-7) << kinds;  // box and cylinder edges rounded by 0.1 um
          EXPECT_GT(d.distance, truth - 1e-5) << kinds;
        } else if (truth < -1e-4) {
          ++overlapping;
          worst_overlap = std::max(worst_overlap, std::abs(d.distance - truth));
          EXPECT_GT(d.distance, truth - 1e-6 - 5e-5 * std::abs(truth)) << kinds;
          EXPECT_LT(d.distance, truth + 3e-5)
              << shapeKindName(shapes[i].kind) << "-" << shapeKindName(shapes[j].kind) << " trial " << trial;
        }
      }
  std::printf("separated %d (worst |error| %.2e m), overlapping %d (worst %.2e m)\n", separated, worst_separated,
              overlapping, worst_overlap);
  EXPECT_GT(separated, 500);
  EXPECT_GT(overlapping, 500);
}

TEST(ShapeContacts, DeepestPointIsTheConvexDistance) {
  std::mt19937 rng(11);
  const auto shapes = primitives();
  int checked = 0;
  for (size_t i = 0; i < shapes.size(); ++i)
    for (size_t j = 0; j < shapes.size(); ++j)
      for (int trial = 0; trial < 100; ++trial) {
        const SE3 pa = randomPose(rng, 0.05), pb = randomPose(rng, 0.25);
        ConvexShape ca, cb;
        convexOf(shapes[i], pa, &ca);
        convexOf(shapes[j], pb, &cb);
        const double truth = convexDistance(ca, cb).distance;  // checked above
        if (truth < -0.05 || truth > 0.02) continue;  // shallow: what a step sees
        ContactPoint pts[kMaxPairPoints];
        const int n = shapeContacts(shapes[i], pa, shapes[j], pb, 0.03, pts);
        ASSERT_GE(n, 1) << i << " " << j;
        EXPECT_NEAR(pts[0].distance, truth, 2e-7)  // the exact point query beside the rounded GJK
            << shapeKindName(shapes[i].kind) << "-" << shapeKindName(shapes[j].kind);
        for (int k = 1; k < n; ++k) EXPECT_GE(pts[k].distance, pts[0].distance);
        // The same inputs, the same points.
        ContactPoint again[kMaxPairPoints];
        ASSERT_EQ(shapeContacts(shapes[i], pa, shapes[j], pb, 0.03, again), n);
        for (int k = 0; k < n; ++k) EXPECT_EQ(again[k].point, pts[k].point);
        ++checked;
      }
  EXPECT_GT(checked, 500);
}

TEST(ShapeContacts, FlatContactsGetSeveralPoints) {
  const CollisionShape plane = shape(Kind::Plane, 0.0);
  const SE3 ground;
  ContactPoint pts[kMaxPairPoints];
  // A box resting on the plane: its four bottom corners at zero gap, normal up.
  const SE3 box_pose{Matrix3::Identity(), Vector3(0.3, -0.2, 0.05)};
  ASSERT_EQ(shapeContacts(plane, ground, shape(Kind::Box, 0.4, 0.3, 0.1), box_pose, 1e-3, pts), 4);
  for (const auto& p : pts) {
    EXPECT_NEAR(p.distance, 0.0, 1e-15);
    EXPECT_EQ(p.normal, Vector3::UnitZ());
    EXPECT_NEAR(std::abs(p.point.x() - 0.3), 0.2, 1e-15);
    EXPECT_NEAR(std::abs(p.point.y() + 0.2), 0.15, 1e-15);
  }
  // The same with the plane second: the normals flip (from the box to the plane).
  ASSERT_EQ(shapeContacts(shape(Kind::Box, 0.4, 0.3, 0.1), box_pose, plane, ground, 1e-3, pts), 4);
  for (const auto& p : pts) EXPECT_EQ(p.normal, -Vector3::UnitZ());
  // A cylinder standing on its cap: four rim points spread round the cap.
  ASSERT_EQ(shapeContacts(plane, ground, shape(Kind::Cylinder, 0.1, 0.3), SE3{Matrix3::Identity(), Vector3(0, 0, 0.15)},
                          1e-3, pts), 4);
  Vector3 mean = Vector3::Zero();
  for (const auto& p : pts) {
    EXPECT_NEAR(p.distance, 0.0, 1e-15);
    EXPECT_NEAR(p.point.head<2>().norm(), 0.1, 1e-12);
    mean += p.point / 4;
  }
  EXPECT_LT(mean.head<2>().norm(), 0.03);  // spread, not bunched on one side
  // A cylinder lying on its side: the two ends of the line it rests on.
  const SE3 lying{Eigen::AngleAxisd(M_PI / 2, Vector3::UnitX()).toRotationMatrix(), Vector3(0, 0, 0.1)};
  ASSERT_EQ(shapeContacts(plane, ground, shape(Kind::Cylinder, 0.1, 0.3), lying, 1e-3, pts), 2);
  EXPECT_NEAR(std::abs(pts[0].point.y() - pts[1].point.y()), 0.3, 1e-12);
  // A capsule lying down: its two ends.
  ASSERT_EQ(shapeContacts(plane, ground, shape(Kind::Capsule, 0.05, 0.3), SE3{lying.R, Vector3(0, 0, 0.05)}, 1e-3, pts),
            2);
  // A box on a larger box: four points, normal up, zero gap.
  const SE3 table{Matrix3::Identity(), Vector3(0, 0, -0.05)};
  const int n = shapeContacts(shape(Kind::Box, 1.0, 1.0, 0.1), table, shape(Kind::Box, 0.2, 0.2, 0.2),
                              SE3{Matrix3::Identity(), Vector3(0.1, 0.1, 0.1)}, 1e-3, pts);
  ASSERT_EQ(n, 4);
  for (int k = 0; k < n; ++k) {
    EXPECT_NEAR(pts[k].distance, 0.0, 1e-12);
    EXPECT_NEAR(pts[k].normal.z(), 1.0, 1e-12);
  }
  // A can standing on a box: four rim points.
  EXPECT_EQ(shapeContacts(shape(Kind::Box, 1.0, 1.0, 0.1), table, shape(Kind::Cylinder, 0.05, 0.2),
                          SE3{Matrix3::Identity(), Vector3(0.1, 0.1, 0.1)}, 1e-3, pts),
            4);
  // A log lying on a box, and a log lying on two logs (a pile), in either order: each touches along a
  // line, so both ends of the line, not one point (a log held at one point turns about it: the pile
  // of three logs slid apart at mu 0.3, above its 2 - sqrt 3 = 0.27).
  const CollisionShape log = shape(Kind::Cylinder, 0.1, 0.4);
  const Matrix3 along_y = Eigen::AngleAxisd(M_PI / 2, Vector3::UnitX()).toRotationMatrix();
  // m points at zero gap spanning the log's 0.4 m along y: the two ends of its line.
  auto expectLineEnds = [&](int m, const char* what, double gap) {
    ASSERT_GE(m, 2) << what;
    double lo = 1.0, hi = -1.0;
    for (int k = 0; k < m; ++k) {
      EXPECT_NEAR(pts[k].distance, 0.0, gap) << what;
      lo = std::min(lo, pts[k].point.y());
      hi = std::max(hi, pts[k].point.y());
    }
    EXPECT_NEAR(hi - lo, 0.4, 1e-9) << what << ": the line's two ends";
  };
  const SE3 on_table{along_y, Vector3(0.05, 0.0, 0.1)};
  expectLineEnds(shapeContacts(log, on_table, shape(Kind::Box, 1.0, 1.0, 0.1), table, 1e-3, pts), "a log on a box", 1e-12);
  expectLineEnds(shapeContacts(shape(Kind::Box, 1.0, 1.0, 0.1), table, log, on_table, 1e-3, pts), "a box under a log",
                 1e-12);
  const SE3 lower{along_y, Vector3(0.1, 0.0, 0.1)}, upper{along_y, Vector3(0.0, 0.0, 0.1 + 0.2 * std::sin(M_PI / 3))};
  expectLineEnds(shapeContacts(log, upper, log, lower, 1e-3, pts), "a log on a log", 1e-9);
  expectLineEnds(shapeContacts(log, lower, log, upper, 1e-3, pts), "a log under a log", 1e-9);
}

TEST(ShapeContacts, AlignedFacesTouchAlongTheFaceNormalExactly) {
  // A box resting on a box, a can standing on a box, both turned together about any axis and pressed
  // in by round-off-sized overlaps: the contact normal is the faces' normal, not EPA's estimate of it
  // (1e-6 off, which tipped a frictionless pyramid of boxes sideways, 6.5e-5 m/s after 3 s).
  std::mt19937 rng(5);
  std::uniform_real_distribution<double> angle(-M_PI, M_PI), overlap(0.0, 1e-6);
  ContactPoint pts[kMaxPairPoints];
  double worst = 0.0;
  for (int trial = 0; trial < 200; ++trial) {
    const Matrix3 R = (Eigen::AngleAxisd(angle(rng), Vector3::UnitZ()) * Eigen::AngleAxisd(angle(rng), Vector3::UnitX()))
                          .toRotationMatrix();
    const SE3 lower{R, R * Vector3(0.0, 0.0, -0.05)};
    const double depth = overlap(rng);
    const CollisionShape upper_shape = trial % 2 ? shape(Kind::Box, 0.1, 0.1, 0.1) : shape(Kind::Cylinder, 0.04, 0.1);
    const SE3 upper{R, R * Vector3(0.013, -0.021, 0.05 - depth)};
    const int n = shapeContacts(shape(Kind::Box, 0.1, 0.1, 0.1), lower, upper_shape, upper, 1e-3, pts);
    ASSERT_GE(n, 3);
    for (int k = 0; k < n; ++k) worst = std::max(worst, (pts[k].normal - R.col(2)).norm());
  }
  std::printf("aligned faces: the normal within %.2e of the faces' normal\n", worst);
  EXPECT_LT(worst, 1e-12);
}

TEST(ShapeContacts, ABoxTippedOverATablesEdgeRestsOnThatEdge) {
  // A box tipped over a table's edge, its face across the edge and 1 mm into it, no corner of either box
  // in the other: the contact is the edge's stretch under the face, both its ends at the face's depth.
  // (The corners alone found one point, or none, and the box sank into the edge as it turned: 0.49 mm in
  // workcell.yaml.)
  const SE3 table{Matrix3::Identity(), Vector3(0, 0, 0)};  // its top at z = 0.05, its edge at y = 0.5
  ContactPoint pts[kMaxPairPoints];
  for (const double tilt : {0.05, 0.3, 0.7}) {
    const Matrix3 R = Eigen::AngleAxisd(-tilt, Vector3::UnitX()).toRotationMatrix();  // its face falls outward
    const double depth = 1e-3;
    const Vector3 face_centre = Vector3(0.0, 0.5, 0.05) + 0.03 * R.col(1) - depth * R.col(2);
    const SE3 box{R, face_centre + 0.1 * R.col(2)};
    for (const bool table_first : {true, false}) {
      const int n = table_first
                        ? shapeContacts(shape(Kind::Box, 1.0, 1.0, 0.1), table, shape(Kind::Box, 0.2, 0.2, 0.2), box, 1e-3, pts)
                        : shapeContacts(shape(Kind::Box, 0.2, 0.2, 0.2), box, shape(Kind::Box, 1.0, 1.0, 0.1), table, 1e-3, pts);
      ASSERT_GE(n, 2) << "tilt " << tilt;
      const Vector3 up = table_first ? R.col(2) : Vector3(-R.col(2));  // from a toward b
      // The edge's two ends under the face, exact; any other point (EPA's) within its 2e-7.
      int ends = 0;
      for (int k = 0; k < n; ++k) {
        const bool end = std::abs(std::abs(pts[k].point.x()) - 0.1) < 1e-12;
        const double tol = end ? 1e-12 : 2e-7;
        ends += end;
        EXPECT_NEAR(pts[k].distance, -depth, tol) << "tilt " << tilt;
        EXPECT_LT((pts[k].normal - up).norm(), 1e-12);
        EXPECT_NEAR(pts[k].point.y(), 0.5 - 0.5 * depth * std::sin(tilt), tol) << "on the edge";
      }
      EXPECT_EQ(ends, 2) << "the edge's stretch under the face, from end to end";
    }
  }
}

// How far two boxes overlap along unit direction u, from their corners (negative: a gap along u).
double boxOverlapAlong(const CollisionShape& a, const SE3& pa, const CollisionShape& b, const SE3& pb, const Vector3& u) {
  auto extent = [&](const CollisionShape& s, const SE3& p, double* lo, double* hi) {
    *lo = std::numeric_limits<double>::infinity();
    *hi = -*lo;
    for (int c = 0; c < 8; ++c) {
      const Vector3 h = 0.5 * s.size;
      const double x = u.dot(p.act(Vector3((c & 1) ? h.x() : -h.x(), (c & 2) ? h.y() : -h.y(), (c & 4) ? h.z() : -h.z())));
      *lo = std::min(*lo, x);
      *hi = std::max(*hi, x);
    }
  };
  double alo, ahi, blo, bhi;
  extent(a, pa, &alo, &ahi);
  extent(b, pb, &blo, &bhi);
  return std::min(ahi - blo, bhi - alo);
}

TEST(ShapeContacts, TwoOverlappingBoxesTakeTheirLeastPenetrationExactly) {
  // Random overlapping pairs of boxes: the deepest point's depth is the least overlap over all
  // directions (200 000 sampled and a local descent from the best, corners projected: no separating
  // axis named), and along the returned normal the boxes overlap by exactly that depth (so no less
  // than the least: the two bound it); every point lies midway between the surfaces.
  std::mt19937 rng(21);
  const CollisionShape boxes[] = {shape(Kind::Box, 0.3, 0.2, 0.1), shape(Kind::Box, 0.05, 0.4, 0.05),
                                  shape(Kind::Box, 0.1, 0.1, 0.1)};
  std::vector<Vector3> directions;
  std::normal_distribution<double> normal;
  for (int k = 0; k < 200000; ++k) directions.push_back(Vector3(normal(rng), normal(rng), normal(rng)).normalized());
  int checked = 0, edges = 0;
  double worst_depth = 0.0, worst_along = 0.0;
  for (int trial = 0; trial < 150; ++trial) {
    const CollisionShape &a = boxes[trial % 3], &b = boxes[(trial / 3) % 3];
    const SE3 pa = randomPose(rng, 0.05), pb = randomPose(rng, 0.12);
    double least = std::numeric_limits<double>::infinity();
    Vector3 best = Vector3::UnitZ();
    auto consider = [&](const Vector3& u) {
      const double o = boxOverlapAlong(a, pa, b, pb, u);
      if (o < least) {
        least = o;
        best = u;
      }
    };
    for (const Vector3& u : directions) consider(u);
    for (double step = 1e-2; step > 1e-12; step *= 0.7)
      for (int k = 0; k < 100; ++k) consider((best + step * Vector3(normal(rng), normal(rng), normal(rng))).normalized());
    if (!(least > 1e-4) || least > 0.05) continue;  // overlapping, as a step may see it
    ContactPoint pts[kMaxPairPoints];
    const int n = shapeContacts(a, pa, b, pb, 1e-3, pts);
    ASSERT_GE(n, 1) << "trial " << trial;
    // The sampled minimum lies above the exact one by the sampling's resolution only.
    EXPECT_LE(-pts[0].distance, least + 1e-12) << "trial " << trial;
    worst_depth = std::max(worst_depth, least + pts[0].distance);
    const double along = boxOverlapAlong(a, pa, b, pb, pts[0].normal);
    worst_along = std::max(worst_along, std::abs(along + pts[0].distance));
    EXPECT_NEAR(along, -pts[0].distance, 1e-12) << "trial " << trial;
    EXPECT_GE(pts[0].normal.dot(pb.p - pa.p), 0.0) << "from a toward b";
    for (int k = 0; k < n; ++k) {
      // Midway between the surfaces: outside neither by more than half its depth.
      EXPECT_LE(pointQuery(a, pa, pts[k].point).distance, 0.5 * std::abs(pts[k].distance) + 1e-12) << "trial " << trial;
      EXPECT_LE(pointQuery(b, pb, pts[k].point).distance, 0.5 * std::abs(pts[k].distance) + 1e-12) << "trial " << trial;
    }
    edges += n == 1;
    ++checked;
  }
  std::printf("overlapping boxes: %d pairs (%d on one point), depth within %.2e of the sampled least, along the "
              "normal within %.2e\n", checked, edges, worst_depth, worst_along);
  EXPECT_GT(checked, 40);
  EXPECT_GT(edges, 0) << "an edge across an edge";
}

TEST(ShapeContacts, AllocatesNothing) {
  const auto shapes = primitives();
  std::mt19937 rng(3);
  ContactPoint pts[kMaxPairPoints];
  std::vector<SE3> poses;
  for (int k = 0; k < 200; ++k) poses.push_back(randomPose(rng, 0.2));
  int total = 0;
  EXPECT_EQ(test::allocationsDuring([&] {
              for (size_t i = 0; i < shapes.size(); ++i)
                for (size_t j = 0; j < shapes.size(); ++j)
                  for (int k = 0; k + 1 < 200; k += 2)
                    total += shapeContacts(shapes[i], poses[k], shapes[j], poses[k + 1], 0.01, pts);
            }),
            0u);
  EXPECT_GT(total, 0);
}

}  // namespace
}  // namespace igms

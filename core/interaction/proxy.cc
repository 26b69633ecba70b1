#include "core/interaction/proxy.h"

#include <algorithm>
#include <cmath>

#include "core/geometry/point_query.h"

namespace igms {

namespace {

constexpr double kTouchSlop = 1e-6;  // m: resting on a surface within this counts as touching it
constexpr double kStopped = 1e-12;   // m: a move shorter than this is none

// The direction the proxy may move toward `goal` without entering the shapes it rests on (normals n):
// the goal's part along the surface, along an edge where two meet, none in a corner.
Vector3 constrainMove(const Vector3& delta, const std::array<ProxyTouch, Proxy::kMaxTouches>& touches, int n) {
  int first = -1;
  Vector3 d = delta;
  for (int pass = 0; pass < 3; ++pass) {
    int worst = -1;
    double most = -kStopped;
    for (int k = 0; k < n; ++k) {
      const double along = d.dot(touches[static_cast<size_t>(k)].normal);
      if (along < most && k != first) {
        most = along;
        worst = k;
      }
    }
    if (worst < 0) return d;
    const Vector3& nw = touches[static_cast<size_t>(worst)].normal;
    if (first < 0) {
      first = worst;
      d = delta - delta.dot(nw) * nw;
      continue;
    }
    Vector3 edge = touches[static_cast<size_t>(first)].normal.cross(nw);
    const double len = edge.norm();
    if (len < 1e-9) return Vector3::Zero();
    edge /= len;
    d = delta.dot(edge) * edge;
    // A third shape in the way: a corner.
    for (int k = 0; k < n; ++k)
      if (d.dot(touches[static_cast<size_t>(k)].normal) < -kStopped) return Vector3::Zero();
    return d;
  }
  return d;
}

}  // namespace

void Proxy::gatherCandidates(const GeometryModel& geometry, const GeometryData& placed, const Vector3& centre,
                             double reach) {
  ncandidates_ = 0;
  const auto& geoms = geometry.objects();
  for (size_t g = 0; g < geoms.size() && g < candidates_.size(); ++g) {
    const GeometryObject& t = geoms[g];
    if (!t.touchable) continue;
    if (!t.plane) {
      const Vector3 c = placed.oMg[g].act(t.box_centre);
      if ((c - centre).norm() > t.radius + reach) continue;
    }
    candidates_[static_cast<size_t>(ncandidates_++)] = static_cast<int>(g);
  }
}

bool Proxy::centreInside(const GeometryModel& geometry, const GeometryData& placed, double radius) {
  const auto& geoms = geometry.objects();
  for (int k = 0; k < ncandidates_; ++k) {
    const int g = candidates_[static_cast<size_t>(k)];
    const PointQuery q = pointQuery(*geoms[static_cast<size_t>(g)].shape, placed.oMg[static_cast<size_t>(g)], p_, 2.0 * radius);
    if (q.valid && q.distance < -kTouchSlop) return true;
  }
  return false;
}

void Proxy::depenetrate(const GeometryModel& geometry, const GeometryData& placed, double radius) {
  const auto& geoms = geometry.objects();
  for (int pass = 0; pass < 4; ++pass) {
    double worst = -kTouchSlop;
    PointQuery out;
    for (int k = 0; k < ncandidates_; ++k) {
      const int g = candidates_[static_cast<size_t>(k)];
      const PointQuery q = pointQuery(*geoms[static_cast<size_t>(g)].shape, placed.oMg[static_cast<size_t>(g)], p_, 2.0 * radius);
      if (!q.valid) continue;
      const double gap = q.distance - radius;
      if (gap < worst) {
        worst = gap;
        out = q;
      }
    }
    if (!out.valid) return;
    p_ = out.surface + radius * out.normal;
  }
}

void Proxy::collectTouches(const GeometryModel& geometry, const GeometryData& placed, double radius) {
  ntouches_ = 0;
  const auto& geoms = geometry.objects();
  for (int k = 0; k < ncandidates_ && ntouches_ < kMaxTouches; ++k) {
    const int g = candidates_[static_cast<size_t>(k)];
    const PointQuery q = pointQuery(*geoms[static_cast<size_t>(g)].shape, placed.oMg[static_cast<size_t>(g)], p_, 2.0 * radius);
    if (!q.valid || q.distance > radius + kTouchSlop) continue;
    touches_[static_cast<size_t>(ntouches_++)] = ProxyTouch{g, q.normal, q.surface};
  }
}

void Proxy::update(const GeometryModel& geometry, const GeometryData& placed, const Vector3& device, double radius,
                   bool free_hold) {
  if (free_hold) {
    last_device_ = device;
    has_device_ = true;
    p_ = device;
    release();
    return;
  }
  const double step = std::max(0.5 * radius, 1e-4);  // a point tip still moves (in 0.1 mm steps)
  // A device that jumped (no hand moves kJump in a cycle: a mapping that changed, a script that started)
  // or a shape that landed over the proxy's centre (a re-based estimate) frees it.
  const bool jumped = has_device_ && (device - last_device_).norm() > kJump;
  last_device_ = device;
  has_device_ = true;
  // What the proxy can meet this cycle: within its travel (at most kMaxSubsteps steps) and its
  // radius. One gather serves the check below and the move (a superset of what the check needs).
  const double travel = std::min((device - p_).norm(), kMaxSubsteps * step);
  if (!free_) {
    gatherCandidates(geometry, placed, p_, travel + 2.0 * radius);
    if (jumped || centreInside(geometry, placed, radius)) release();
  }
  if (free_) {
    // Engage where the device is clear of everything, or no deeper than kEngageDepth.
    const double engage = radius - std::min(radius, kEngageDepth) - kTouchSlop;
    p_ = device;
    gatherCandidates(geometry, placed, device, radius);
    const auto& geoms = geometry.objects();
    for (int k = 0; k < ncandidates_; ++k) {
      const int g = candidates_[static_cast<size_t>(k)];
      const PointQuery q = pointQuery(*geoms[static_cast<size_t>(g)].shape, placed.oMg[static_cast<size_t>(g)], device, 2.0 * radius);
      if (q.valid && q.distance < engage) return;  // deeper: stays free
    }
    free_ = false;
    depenetrate(geometry, placed, radius);
    collectTouches(geometry, placed, radius);
    return;
  }
  depenetrate(geometry, placed, radius);  // what moved into it since the last cycle
  collectTouches(geometry, placed, radius);
  int s = 0;
  for (; s < kMaxSubsteps; ++s) {
    const Vector3 goal = device - p_;
    Vector3 move = constrainMove(goal, touches_, ntouches_);
    double len = move.norm();
    if (friction_ > 0.0 && ntouches_ > 0) {
      // Coulomb: the move along the surface is what the tangential pull has beyond mu times the normal one.
      double normal = 0.0;
      for (int k = 0; k < ntouches_; ++k) normal = std::max(normal, -goal.dot(touches_[static_cast<size_t>(k)].normal));
      const double slide = len - friction_ * normal;
      if (slide <= 0.0) break;  // inside the cone: it sticks
      move *= slide / len;
      len = slide;
    }
    if (len < kStopped) break;
    if (len > step) move *= step / len;
    p_ += move;
    depenetrate(geometry, placed, radius);
    collectTouches(geometry, placed, radius);
  }
  if (s == kMaxSubsteps) ++substep_limited_;
}

int Proxy::deepest(const GeometryModel& geometry, const Vector3& device, bool movable_only) const {
  int best = -1;
  double depth = 0.0;
  for (int k = 0; k < ntouches_; ++k) {
    const ProxyTouch& t = touches_[static_cast<size_t>(k)];
    if (movable_only && geometry.object(t.geom).body < 0) continue;
    const double d = (p_ - device).dot(t.normal);
    if (d > depth) {
      depth = d;
      best = k;
    }
  }
  return best;
}

int Proxy::nearestMovable(const GeometryModel& geometry, const GeometryData& placed, double radius,
                          double reach) const {
  if (free_) return -1;
  int best = -1;
  double nearest = radius + reach;
  for (int k = 0; k < ncandidates_; ++k) {
    const int g = candidates_[static_cast<size_t>(k)];
    const GeometryObject& t = geometry.object(g);
    if (t.body < 0) continue;
    const PointQuery q = pointQuery(*t.shape, placed.oMg[static_cast<size_t>(g)], p_, nearest);
    if (q.valid && q.distance < nearest) {
      nearest = q.distance;
      best = g;
    }
  }
  return best;
}

Vector3 Proxy::stretch(const Vector3& device) const {
  if (free_ || ntouches_ == 0) return Vector3::Zero();
  return p_ - device;
}

}  // namespace igms

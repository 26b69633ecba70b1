#include "tools/ode_ref/ode_contact_scene.h"

#include <ode/ode.h>

#include <memory>
#include <mutex>
#include <stdexcept>

#include "core/geometry/shape_inertia.h"
#include "core/geometry/shape_surface.h"

namespace igms {

namespace {
std::once_flag g_init;

void setRotation(dGeomID g, const Matrix3& R) {
  dMatrix3 m;
  for (int r = 0; r < 3; ++r) {
    for (int c = 0; c < 3; ++c) m[4 * r + c] = R(r, c);
    m[4 * r + 3] = 0.0;
  }
  dGeomSetRotation(g, m);
}

// A shape ODE has no primitive for, as its triangles (core/geometry/shape_surface.h): ODE reads the
// arrays for as long as the geom lives.
struct OdeTriangles {
  std::vector<dReal> vertices;
  std::vector<dTriIndex> indices;
  dTriMeshDataID data = nullptr;
  ~OdeTriangles() {
    if (data) dGeomTriMeshDataDestroy(data);
  }
};

dGeomID makeGeom(dSpaceID space, const CollisionShape& s, const std::string& what,
                 std::vector<std::unique_ptr<OdeTriangles>>& keep) {
  switch (s.kind) {
    case CollisionShape::Kind::Box: return dCreateBox(space, s.size[0], s.size[1], s.size[2]);
    case CollisionShape::Kind::Sphere: return dCreateSphere(space, s.size[0]);
    case CollisionShape::Kind::Cylinder: return dCreateCylinder(space, s.size[0], s.size[1]);
    case CollisionShape::Kind::Capsule: return dCreateCapsule(space, s.size[0], s.size[1]);
    default: break;  // a mesh, and any kind ODE has no primitive for: its surface's triangles
  }
  const TriangleMesh surface = shapeSurface(s);
  if (surface.triangles.empty()) throw std::invalid_argument(what + ": no triangles for ODE's trimesh");
  auto t = std::make_unique<OdeTriangles>();
  for (const Vector3& v : surface.vertices) t->vertices.insert(t->vertices.end(), {v.x(), v.y(), v.z()});
  for (const auto& tri : surface.triangles)
    for (int i : tri) t->indices.push_back(static_cast<dTriIndex>(i));
  t->data = dGeomTriMeshDataCreate();
  dGeomTriMeshDataBuildDouble(t->data, t->vertices.data(), 3 * sizeof(dReal), static_cast<int>(surface.vertices.size()),
                              t->indices.data(), static_cast<int>(t->indices.size()), 3 * sizeof(dTriIndex));
  dGeomID g = dCreateTriMesh(space, t->data, nullptr, nullptr, nullptr);
  keep.push_back(std::move(t));
  return g;
}
}  // namespace

struct OdeContactScene::Impl {
  OdeContactSettings settings;
  dWorldID world = nullptr;
  dSpaceID space = nullptr;
  dJointGroupID contacts = nullptr;
  std::vector<dBodyID> bodies;
  std::vector<std::string> names;
  std::vector<Material> body_material;  // per ODE body
  std::vector<Material> static_material;
  std::vector<dGeomID> statics;
  std::vector<std::unique_ptr<OdeTriangles>> triangles;  // the trimeshes' arrays, freed after the space
  double bounce_velocity = 0.0;
  int last_contacts = 0;

  Material materialOf(dGeomID g) const {
    const dBodyID b = dGeomGetBody(g);
    for (size_t k = 0; k < bodies.size(); ++k)
      if (bodies[k] == b) return body_material[k];
    for (size_t k = 0; k < statics.size(); ++k)
      if (statics[k] == g) return static_material[k];
    return Material{};
  }

  void collide(dGeomID a, dGeomID b) {
    const dBodyID ba = dGeomGetBody(a), bb = dGeomGetBody(b);
    if (!ba && !bb) return;
    dContact c[16];
    const int n = dCollide(a, b, std::min(settings.max_points, 16), &c[0].geom, sizeof(dContact));
    const Material m = combine(materialOf(a), materialOf(b));
    for (int k = 0; k < n; ++k) {
      dSurfaceParameters& s = c[k].surface;
      s.mode = dContactApprox1 | dContactSoftERP | dContactSoftCFM;
      s.mu = m.friction;
      s.soft_erp = settings.erp;
      s.soft_cfm = settings.cfm;
      if (m.restitution > 0.0) {
        s.mode |= dContactBounce;
        s.bounce = m.restitution;
        s.bounce_vel = bounce_velocity;
      }
      // fdir1 along the slip at the point, so that the pyramid's first direction opposes it.
      const dReal* p = c[k].geom.pos;
      const dReal* nrm = c[k].geom.normal;
      dVector3 va = {0, 0, 0, 0}, vb = {0, 0, 0, 0};
      if (ba) dBodyGetPointVel(ba, p[0], p[1], p[2], va);
      if (bb) dBodyGetPointVel(bb, p[0], p[1], p[2], vb);
      const Vector3 n(nrm[0], nrm[1], nrm[2]);
      Vector3 slip(va[0] - vb[0], va[1] - vb[1], va[2] - vb[2]);
      slip -= slip.dot(n) * n;
      if (slip.norm() > 1e-9) {
        slip.normalize();
        s.mode |= dContactFDir1;
        for (int i = 0; i < 3; ++i) c[k].fdir1[i] = slip[i];
      }
      dJointAttach(dJointCreateContact(world, contacts, &c[k]), ba, bb);
      ++last_contacts;
    }
  }
  static void nearCallback(void* data, dGeomID a, dGeomID b) { static_cast<Impl*>(data)->collide(a, b); }
};

OdeContactScene::OdeContactScene(const ResolvedScene& r, const OdeContactSettings& settings)
    : impl_(std::make_unique<Impl>()) {
  const Scene& s = r.scene;
  if (!s.robots.empty()) throw std::invalid_argument(s.source + ": ODE's contact reference takes free bodies only");
  std::call_once(g_init, [] { dInitODE2(0); });
  Impl& m = *impl_;
  m.settings = settings;
  m.bounce_velocity = s.contact.bounce_velocity;
  m.world = dWorldCreate();
  dWorldSetGravity(m.world, s.gravity.x(), s.gravity.y(), s.gravity.z());
  dWorldSetERP(m.world, settings.erp);
  dWorldSetCFM(m.world, settings.cfm);
  dWorldSetQuickStepNumIterations(m.world, settings.quickstep_iterations);
  dWorldSetAutoDisableFlag(m.world, 0);
  m.space = dSimpleSpaceCreate(nullptr);
  m.contacts = dJointGroupCreate(0);
  auto material = [&](const std::string& name) { return s.materials.at(name.empty() ? "default" : name); };
  for (size_t k = 0; k < s.bodies.size(); ++k) {
    const FreeBodySpec& b = s.bodies[k];
    const ModelPart& part = r.model->parts[k];
    const SpatialInertia& I = r.model->inertia[static_cast<size_t>(part.body_begin)];
    dBodyID body = dBodyCreate(m.world);
    dMass mass;
    const Vector3 c = I.com();
    const Matrix3 Ic = I.inertiaAboutCom();
    dMassSetParameters(&mass, I.m, 0, 0, 0, Ic(0, 0), Ic(1, 1), Ic(2, 2), Ic(0, 1), Ic(0, 2), Ic(1, 2));
    if (c.norm() > 1e-12) throw std::invalid_argument(s.source + ": " + b.name + ": its centre of mass is off its shape's centre");
    dBodySetMass(body, &mass);
    const Vector3 p = b.pose.p;
    dBodySetPosition(body, p.x(), p.y(), p.z());
    const Eigen::Quaterniond q(b.pose.R);
    const dQuaternion dq = {q.w(), q.x(), q.y(), q.z()};
    dBodySetQuaternion(body, dq);
    dBodySetLinearVel(body, b.velocity.x(), b.velocity.y(), b.velocity.z());
    dBodySetAngularVel(body, b.angular_velocity.x(), b.angular_velocity.y(), b.angular_velocity.z());
    dGeomID g = makeGeom(m.space, b.shape, s.source + ": " + b.name, m.triangles);
    dGeomSetBody(g, body);
    m.bodies.push_back(body);
    m.names.push_back(b.name);
    m.body_material.push_back(material(b.material));
  }
  if (s.ground.enabled) {
    const Vector3 n = s.ground.pose.R.col(2);
    m.statics.push_back(dCreatePlane(m.space, n.x(), n.y(), n.z(), n.dot(s.ground.pose.p)));
    m.static_material.push_back(material(s.ground.material));
  }
  for (const Obstacle& o : s.obstacles) {
    if (!o.solid) continue;
    dGeomID g = makeGeom(m.space, o.shape, s.source + ": obstacle " + o.name, m.triangles);
    dGeomSetPosition(g, o.shape.placement.p.x(), o.shape.placement.p.y(), o.shape.placement.p.z());
    setRotation(g, o.shape.placement.R);
    m.statics.push_back(g);
    m.static_material.push_back(material(o.material));
  }
}

OdeContactScene::~OdeContactScene() {
  dJointGroupDestroy(impl_->contacts);
  dSpaceDestroy(impl_->space);
  dWorldDestroy(impl_->world);
}

void OdeContactScene::step(double h) {
  Impl& m = *impl_;
  m.last_contacts = 0;
  dSpaceCollide(m.space, &m, &Impl::nearCallback);
  if (m.settings.quickstep) dWorldQuickStep(m.world, h);
  else dWorldStep(m.world, h);
  dJointGroupEmpty(m.contacts);
}

int OdeContactScene::bodies() const { return static_cast<int>(impl_->bodies.size()); }
const std::string& OdeContactScene::name(int k) const { return impl_->names[static_cast<size_t>(k)]; }
int OdeContactScene::contactsLastStep() const { return impl_->last_contacts; }

SE3 OdeContactScene::pose(int k) const {
  const dBodyID b = impl_->bodies[static_cast<size_t>(k)];
  const dReal* p = dBodyGetPosition(b);
  const dReal* q = dBodyGetQuaternion(b);
  return SE3{Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized().toRotationMatrix(), Vector3(p[0], p[1], p[2])};
}

Vector3 OdeContactScene::velocity(int k) const {
  const dReal* v = dBodyGetLinearVel(impl_->bodies[static_cast<size_t>(k)]);
  return Vector3(v[0], v[1], v[2]);
}

Vector3 OdeContactScene::angularVelocity(int k) const {
  const dReal* v = dBodyGetAngularVel(impl_->bodies[static_cast<size_t>(k)]);
  return Vector3(v[0], v[1], v[2]);
}

}  // namespace igms

// The robot coupled to the user, as the integrators see it: f(q, v) = qdd
// under the controller torque held over the step, joint damping, the joint
// limits (joint_limits.h), the hold damping, and the users' pushes (eq. 3, U_E = J^T c) and pulls
// (eq. 4, tau = J^T F, F a force and, for a device with an orientation, a torque) computed against
// the state being evaluated. Several hands act at once: their couplings are summed, in the
// dynamics and in the implicit step's linearisation alike.
//
// Everything a step holds constant is an argument (CoupledInputs), and
// every evaluation returns its results (CoupledEvaluation: acceleration,
// H qdd, the user's force and its linearisation). Nothing is left behind in
// the object for a caller to read later.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/contact/contact_set.h"
#include "core/contact/contact_solver.h"
#include "core/dynamics/external_force.h"
#include "core/geometry/geometry_model.h"
#include "core/integrate/free_body_motion.h"
#include "core/scene/scene.h"
#include "core/simulation/hand_input.h"
#include "core/simulation/joint_limits.h"

namespace igms {

// One hand's coupling over one step: the device state and the gains.
// The gains every hand's coupling takes: the scene's, or a SET_GAINS command's. push_b: the virtual
// coupling's damper on the tip's approach to the touched point (N s/m).
struct CouplingGains {
  double push_k_p = 0.0, push_b = 0.0, pull_k = 0.0, pull_b = 0.0, pull_k_rot = 0.0, pull_b_rot = 0.0;
};

// One hand acting in a step: its input as the bus edge validated it (the one input type, from the
// bus to here: hand_input.h), and what the step resolved for it.
struct Coupling {
  InteractionInput hand;
  // Push: the shape the hand's proxy rests on (proxy.h), on frame contact_frame at push_placement;
  // null: the proxy touches nothing that moves, no push. The depth is the tip's behind that
  // shape's surface under the proxy, at each evaluated state.
  int contact_frame = -1;
  const CollisionShape* push_shape = nullptr;
  SE3 push_placement;
  Vector3 proxy = Vector3::Zero();
  // Pull: the link and point the spring pulls (the input's, or the scene's pull link and point).
  int pull_frame = -1;
  Vector3 pull_point = Vector3::Zero();  // in that link's frame
  // The 6-D pull: the input's orientations as matrices (world <- tip; link <- grasp), once a step.
  Matrix3 tip_rotation = Matrix3::Identity();
  Matrix3 attach_rotation = Matrix3::Identity();
  CouplingGains gains;
  // A resume ramp (simulation.h): its share of the way, (0, 1], from what the hand gave before its gap
  // (the sizes of its force and torque on this frame then) to its whole coupling now. 1: no ramp.
  double scale = 1.0;
  double carried_force = 0.0, carried_torque = 0.0;
  int robot = -1;      // the robot this hand holds (HandTrack::holdRobot), -1: none

  // The frame the hand acts on: the pushed shape's, or the pulled link (-1: a push on nothing).
  int actsOn() const {
    return hand.mode == InteractionMode::Push ? (push_shape ? contact_frame : -1)
           : hand.mode == InteractionMode::Pull ? pull_frame
                                                : -1;
  }
};

// Dofs [begin, end) of one tree (a robot's), and the hold's rate there.
struct DofRange {
  int begin = 0, end = 0;
  double rate = 0.0;
};

// The joint PD of robots that stand or follow by PD (ControllerKind::Pd), per dof: tau += kp (q_ref - q)
// + kd (v_ref - v) on the joints where kp or kd is non-zero, taken implicitly by the linearly-implicit step.
struct JointPd {
  const VectorX* kp = nullptr;     // nv
  const VectorX* kd = nullptr;     // nv
  const VectorX* q_ref = nullptr;  // nv: the joint's reference coordinate, at its dof
  const VectorX* v_ref = nullptr;  // nv
};

struct CoupledInputs {
  VectorX& tau;                // controller torque, held over the step (see inverse_dynamics)
  const Coupling* couplings;   // the hands, in a stated order (the server's: by client id)
  int ncouplings;
  // The controller as inverse dynamics at the step's start state: the step's first evaluation
  // (every scheme's is at the start) writes tau = rnea(q0, v0, *qdd_cmd), the computed torque, or
  // with qdd_cmd null b(q0, v0), the hold's gravity and Coriolis compensation; plus D v0 when the
  // scene has joint damping; zero on a floating base's six unactuated coordinates. It comes from
  // the same pass as the plant's bias (rneaAndBias): the two share placements and velocities.
  bool inverse_dynamics = false;
  const VectorX* qdd_cmd = nullptr;
  // The hold, -rate H v, acts on each held robot's dofs (hold; null or empty: none), and inverse
  // dynamics drives none of the uncommanded dofs (passive robots, PD robots); floating joints it never
  // drives.
  const std::vector<DofRange>* hold = nullptr;
  const std::vector<DofRange>* uncommanded = nullptr;
  JointPd pd = {};
  // The step's contacts (the detection stage's, at its start state); the contact solve writes their
  // impulses. Null without contact.
  ContactSet* contacts = nullptr;
};

// The user's force at one evaluated state, and its linearisation.
struct CouplingForce {
  bool coupled = false;
  int frame = -1;
  Vector3 point_local = Vector3::Zero();  // where it acts, link frame
  HandForce applied;                      // on the link, and where in the world
  Matrix3 K = Matrix3::Zero(), B = Matrix3::Zero();  // -dF/dx, -dF/dxdot at the point (zero when capped)
  // -dT/dtheta, -dT/domega: k_rot I and b_rot I (the small-angle linearisation
  // of the log map: symmetric, so the implicit step's matrix stays SPD), zero when capped.
  double k_rot = 0.0, b_rot = 0.0;
};

struct CoupledEvaluation {
  VectorX qdd;  // NaN when H was singular (the divergence guard catches it)
  VectorX F;    // H qdd
  std::array<CouplingForce, kMaxHands> couplings;  // the first ncouplings, in the inputs' order
  int ncouplings = 0;
  VectorX limit_k, limit_b;  // per velocity coordinate: the joint limits acting here (joint_limits.h), else 0
};

class CoupledDynamics {
 public:
  // q_reference: where the joint limits take their gains (the scene's initial state). contacts: the
  // environment's (null or empty: one robot in empty space, no contact step).
  CoupledDynamics(const Model& model, const Scene& scene, const VectorX& q_reference,
                  const ContactModel* contacts = nullptr);

  CoupledEvaluation makeEvaluation() const;
  // A step's first stage (Simulation::step calls it before the dynamics): the bodies at q, the step's
  // start state (which the start evaluation then reuses), and the geometry at them.
  void placeGeometry(const VectorX& q, const GeometryModel& geometry, GeometryData& placed);
  // step_start: (q, v) is the step's start state, where in.inverse_dynamics resolves in.tau and the
  // contact solve acts on in.contacts.
  void evaluate(const CoupledInputs& in, const VectorX& q, const VectorX& v, CoupledEvaluation& out,
                bool step_start = true);
  // A = H + h D + h^2 K, rhs = h (F - h K v) at `at`, the most recent evaluation; a free body's block
  // that is its inertia alone (nothing added: no hand on it, no damping) written as its factors, kept
  // from the first step, and marked in `factored` (per block of A).
  void linearSystem(const CoupledInputs& in, const CoupledEvaluation& at, const VectorX& v, double h, TreeMatrix& A,
                    VectorX& rhs, std::vector<char>& factored);
  // The couplings' forces a linearly-implicit step applied, from v (its start) to v_end (its end, the
  // contact step's included): the stiff terms are taken at the end of the step, H dv = h (F - h K v+
  // - D dv), so each hand's force was f - K h J v+ - B J (v+ - v) at its point (and its moment
  // t - k_rot h Jw v+ - b_rot Jw (v+ - v)), J at the start (linearSystem's). Writes `applied` (the
  // start evaluation's couplings with those forces); allocates nothing.
  void appliedCouplings(const CoupledEvaluation& at, const VectorX& v, const VectorX& v_end, double h,
                        std::array<CouplingForce, kMaxHands>& applied) const;
  // The contact step (contact_solver.h) after the unconstrained update: v holds v_free and becomes v+;
  // factored: the matrix the step solved with, factored (null: H's, from the start evaluation).
  void constrain(const CoupledInputs& in, const VectorX& v0, double h, const TreeMatrix* factored, VectorX& v,
                 VectorX& v_position);
  bool hasContacts() const { return contacts_ != nullptr; }
  // With contact, the linearly-implicit step needs H but not its factors: the acceleration a step
  // reports is then the one it applied, (v+ - v) / h, contact included (what a standing robot does,
  // not the free fall its start state alone would give), and evaluate() leaves qdd unset.
  void reportAppliedAcceleration(bool on) { applied_acceleration_ = on; }
  const ContactSolveStats& contactStats() const;
  // Forget the contact solve's warm start (a reset state).
  void resetContacts();

  // The evaluator the integrators take (integrators.h): these dynamics with
  // one step's inputs bound. Its first evaluation is the step's start state.
  class StepEvaluator {
   public:
    using Evaluation = CoupledEvaluation;
    StepEvaluator(CoupledDynamics& d, const CoupledInputs& in) : d_(d), in_(in) {}
    Evaluation makeEvaluation() const { return d_.makeEvaluation(); }
    void evaluate(const VectorX& q, const VectorX& v, Evaluation& out) {
      d_.evaluate(in_, q, v, out, !started_);
      started_ = true;
    }
    void linearSystem(const Evaluation& at, const VectorX& v, double h, TreeMatrix& A, VectorX& rhs,
                      std::vector<char>& factored) {
      d_.linearSystem(in_, at, v, h, A, rhs, factored);
    }
    bool hasContacts() const { return d_.hasContacts(); }
    void constrain(const VectorX& v0, double h, const TreeMatrix* factored, VectorX& v, VectorX& v_position) {
      d_.constrain(in_, v0, h, factored, v, v_position);
    }
    FreeBodyMotion* freeBodies() { return &d_.free_bodies_; }

   private:
    CoupledDynamics& d_;
    const CoupledInputs& in_;
    bool started_ = false;
  };
  StepEvaluator bind(const CoupledInputs& in) { return StepEvaluator(*this, in); }

 private:
  // One hand's force at (q, v) as placed (push: eq. 3; pull: eq. 4, with its rotational half).
  void couplingForce(const Coupling& c, const VectorX& v, CouplingForce& out);
  static double rampShare(double scale, double carried, double now);
  // The hold's damping -c H v on F (per held robot's block, or on all), and -c v on qdd when given.
  void subtractHoldDamping(const CoupledInputs& in, const VectorX& v, VectorX& F, VectorX* qdd) const;

  const Model& model_;
  const Scene& scene_;
  JointLimits limits_;
  std::vector<DofRange> floating_;  // floating joints: never driven
  const ContactModel* contacts_ = nullptr;
  FreeBodyMotion free_bodies_;  // the free bodies' own step (a hand's: the integrators')
  bool applied_acceleration_ = false;
  std::unique_ptr<ContactSolver> solver_;
  bool placed_ = false;  // placeGeometry ran for the step whose start evaluation is next
  Data data_;
  VectorX tau_total_;
  std::vector<Force> fext_;
  Matrix6X KJ_;
  Matrix6X J_;
  std::array<Matrix6X, kMaxHands> coupling_J_;  // each coupling's point Jacobian at the step's start
  // The free bodies' blocks of H (their inertia in their own frame: the same at every pose) and their
  // factors, formed once: a block of A equal to its inertia takes them (ltdlFactor would give the
  // same bits again) where a pile's thousand blocks were factored every step.
  std::vector<int> free_blocks_;   // blocks of H that are one free body
  TreeMatrix free_inertia_, free_factors_;
};

}  // namespace igms

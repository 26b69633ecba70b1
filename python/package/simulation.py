"""igms.Simulation: the native step with what reads better in Python on top:
each body's pose and velocity, the contacts as one structured array, and the hands."""
import numpy as np

from ._igms import Simulation as _NativeSimulation

CONTACT_DTYPE = np.dtype([
    ("body_a", "U64"), ("body_b", "U64"),  # the bodies' link names ("world": fixed)
    ("geom_a", "U64"), ("geom_b", "U64"),  # the touching shapes' names
    ("point", "f8", (3,)),                 # world, m: midway between the surfaces
    ("normal", "f8", (3,)),                # world, unit, from a toward b
    ("impulse", "f8", (3,)),               # world, N s over the step, on b (a gets the opposite)
    ("depth", "f8"),                       # m: overlap at the step's start (negative: apart)
])


class Body:
    """A body's (or any link's) state at the current step: pose (4 x 4, world <- body), velocity
    [linear velocity of its origin; angular], world axes."""

    def __init__(self, name, pose, velocity):
        self.name, self.pose, self.velocity = name, pose, velocity

    @property
    def position(self):
        return self.pose[:3, 3]

    @property
    def rotation(self):
        return self.pose[:3, :3]

    def __repr__(self):
        return f"Body({self.name!r}, position={self.position.tolist()}, velocity={self.velocity.tolist()})"


class Hands:
    """Up to four hands (clients 0..3), each a push or a pull held until released; every step sends each
    held hand's input again with the next seq, as a device held still on the bus would."""

    def __init__(self, sim):
        self._sim = sim

    def push(self, tip, velocity=(0.0, 0.0, 0.0), radius=0.01, link="", client=0):
        """The tip sphere at `tip` (world, m) pushes what it penetrates: c = k_p d (eq. 3). link: only that
        link (default: any link with collision shapes)."""
        self._sim._push(client, tip, velocity, float(radius), link)

    def pull(self, tip, velocity=(0.0, 0.0, 0.0), link="", point=(0.0, 0.0, 0.0), orientation=None,
             angular_velocity=None, grasp=None, client=0):
        """A spring-damper from `tip` to `point` of `link` (default: the scene's pull link), eq. (4); with an
        orientation (w, x, y, z) the 6-D pull, grasp the grasped frame in the link."""
        self._sim._pull(client, tip, velocity, link, point, orientation, angular_velocity, grasp)

    def release(self, client=0):
        self._sim._release(client)

    def clear(self):
        for c in self.active:
            self.release(c)

    @property
    def active(self):
        """The clients holding a push or a pull."""
        return self._sim._active_hands()

    def outcome(self):
        """Each hand's part of the last step: client, mode, force and torque on the robot (world), point."""
        return self._sim._hand_outcomes()


class Simulation(_NativeSimulation):
    """The server's step on a scene: step(n) without the GIL; q, v read-only views (set_state writes);
    body(name), contacts(), hands, summary()."""

    @property
    def hands(self):
        return Hands(self)

    def body(self, name):
        pose, velocity = self._body(name)
        return Body(name, pose, velocity)

    def contacts(self):
        """The contacts at the last step's start, with the impulses its solve gave them (CONTACT_DTYPE)."""
        columns = self._contact_columns()
        out = np.zeros(len(columns["depth"]), dtype=CONTACT_DTYPE)
        for field in CONTACT_DTYPE.names:
            out[field] = columns[field]
        return out

    def __repr__(self):
        return f"<igms.Simulation t={self.time:.6g} s, nq={self.nq}, bodies={self.bodies}>"

"""igms.Model's kernels from Python against each other, finite differences and the paper's identities,
on the PUMA 560, the UR5 (example-robot-data) and a floating-base quadruped."""
import numpy as np
import pytest

import igms
from conftest import robot

MODELS = [("models/puma560.urdf", False), ("ur_description/urdf/ur5_robot.urdf", False),
          ("models/quadruped.urdf", True)]


def load(path, floating):
    return igms.Model.from_urdf(path if path.startswith("models/") else robot(path), floating_base=floating)


def state(model, rng):
    q = model.neutral()
    n = model.nv - (6 if model.nq != model.nv else 0)
    q[model.nq - n:] = rng.uniform(-1.0, 1.0, n)
    if model.nq != model.nv:  # a free joint: somewhere, turned
        q[:3] = rng.uniform(-1, 1, 3)
        quat = rng.normal(size=4)
        q[3:7] = quat / np.linalg.norm(quat)
    return q, rng.uniform(-1, 1, model.nv), rng.uniform(-1, 1, model.nv)


@pytest.mark.parametrize("path,floating", MODELS)
def test_inverse_and_forward_dynamics_agree(path, floating):
    model = load(path, floating)
    rng = np.random.default_rng(3)
    for _ in range(5):
        q, v, a = state(model, rng)
        tau = model.rnea(q, v, a)
        H = model.crba(q)
        assert np.allclose(H, H.T, atol=1e-12)
        assert np.all(np.linalg.eigvalsh(H) > 0)
        bias = model.rnea(q, v, np.zeros(model.nv))
        np.testing.assert_allclose(H @ a + bias, tau, rtol=1e-10, atol=1e-10)
        np.testing.assert_allclose(model.aba(q, v, tau), a, rtol=1e-9, atol=1e-9)
        np.testing.assert_allclose(model.forward_dynamics(q, v, tau), a, rtol=1e-9, atol=1e-9)


@pytest.mark.parametrize("path,floating", MODELS[:2])
def test_jacobian_is_the_placements_derivative(path, floating):
    model = load(path, floating)
    rng = np.random.default_rng(5)
    q, _, _ = state(model, rng)
    frame = model.frame_names[-1]
    J = model.frame_jacobian(q, frame)
    assert J.shape == (6, model.nv)
    eps = 1e-7
    for k in range(model.nv):
        dq = np.zeros(model.nq)
        dq[k] = eps
        plus, minus = model.frame_placement(q + dq, frame), model.frame_placement(q - dq, frame)
        np.testing.assert_allclose((plus[:3, 3] - minus[:3, 3]) / (2 * eps), J[:3, k], atol=1e-7)
        dR = (plus[:3, :3] - minus[:3, :3]) / (2 * eps) @ model.frame_placement(q, frame)[:3, :3].T
        np.testing.assert_allclose([dR[2, 1], dR[0, 2], dR[1, 0]], J[3:, k], atol=1e-7)


def test_names_and_sizes():
    model = igms.Model.from_urdf("models/puma560.urdf")
    assert (model.nq, model.nv) == (6, 6)
    assert "link2" in model.frame_names
    floating = igms.Model.from_urdf("models/puma560.urdf", floating_base=True)
    assert (floating.nq, floating.nv) == (13, 12)
    placement = model.frame_placement(model.neutral(), "link2")
    np.testing.assert_allclose(placement, model.frame_placement(model.neutral(), model.frame_names.index("link2")))


def test_arrays_are_checked_before_anything_runs():
    model = igms.Model.from_urdf("models/puma560.urdf")
    z = np.zeros(6)
    np.testing.assert_array_equal(model.rnea([0] * 6, z, z), model.rnea(z.astype(np.float32), z, z.astype(int)))
    with pytest.raises(ValueError, match=r"q: expected shape \(6,\), got \(5,\)"):
        model.rnea(np.zeros(5), z, z)
    with pytest.raises(ValueError, match=r"v: expected shape \(6,\), got \(2, 3\)"):
        model.rnea(z, np.zeros((2, 3)), z)
    with pytest.raises(ValueError, match=r"a\[2\] is not finite"):
        model.rnea(z, z, np.array([0, 0, np.nan, 0, 0, 0]))
    with pytest.raises(ValueError, match=r"tau\[0\] is not finite"):
        model.aba(z, z, np.array([np.inf, 0, 0, 0, 0, 0]))
    for wrong in (["a"] * 6, np.zeros(6, complex), np.array([None] * 6), np.zeros(6, bool)):
        with pytest.raises(TypeError, match=r"q: expected an array of real numbers, got dtype"):
            model.rnea(wrong, z, z)
    with pytest.raises(KeyError, match="no frame 'nope'"):
        model.frame_placement(z, "nope")
    with pytest.raises(IndexError):
        model.frame_jacobian(z, 99)


def test_model_errors_name_the_file(tmp_path):
    with pytest.raises(igms.ModelError, match="nope.urdf"):
        igms.Model.from_urdf("nope.urdf")
    bad = tmp_path / "bad.urdf"
    bad.write_text("<robot name='x'><link name='a'/><joint name='j' type='revolute'><parent link='a'/></joint></robot>")
    with pytest.raises(igms.ModelError, match="bad.urdf"):
        igms.Model.from_urdf(str(bad))

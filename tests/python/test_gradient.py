"""Suite.robustness_gradient: rho and d rho / d(input values), against central differences."""
import numpy as np
import pytest

import hyfal


def _signal(seed):
    t = np.arange(0.0, 31.0, 1.0)
    rng = np.random.default_rng(seed)
    return t, {"throttle": rng.uniform(0, 100, len(t)), "brake": rng.uniform(0, 325, len(t))}


@pytest.mark.parametrize("interpolation", ["zoh", "linear"])
def test_the_gradient_matches_central_differences(interpolation):
    s = hyfal.Suite("at")
    t, u = _signal(1)
    rho, g = s.robustness_gradient("AT1", u, t, interpolation=interpolation)
    assert rho == s.robustness("AT1", s.simulate(u, t, interpolation=interpolation))
    assert set(g) == {"throttle", "brake"}  # keyed as the inputs were
    assert g["throttle"].shape == u["throttle"].shape
    for name, k in [("throttle", 3), ("throttle", 10), ("brake", 5)]:
        h = 1e-5 * (100 if name == "throttle" else 325)
        up = {n: v.copy() for n, v in u.items()}
        down = {n: v.copy() for n, v in u.items()}
        up[name][k] += h
        down[name][k] -= h
        fd = (s.robustness("AT1", s.simulate(up, t, interpolation=interpolation))
              - s.robustness("AT1", s.simulate(down, t, interpolation=interpolation))) / (2 * h)
        assert g[name][k] == pytest.approx(fd, rel=1e-5, abs=1e-9), (name, k)
    if interpolation == "zoh":
        assert g["throttle"][-1] == 0.0  # the last value holds for no time


def test_an_array_of_inputs_gives_the_gradient_by_input_name():
    s = hyfal.Suite("at")
    t, u = _signal(2)
    rho, g = s.robustness_gradient("AT1", np.column_stack([u["throttle"], u["brake"]]), t)
    assert set(g) == {"u1", "u2"}
    rho_alias, by_alias = s.robustness_gradient("AT1", u, t)
    assert rho == rho_alias
    np.testing.assert_array_equal(g["u1"], by_alias["throttle"])
    np.testing.assert_array_equal(g["u2"], by_alias["brake"])


def test_a_step_along_the_gradient_lowers_rho():
    s = hyfal.Suite("at")
    t, u = _signal(3)
    rho, g = s.robustness_gradient("AT1", u, t)
    step = {n: np.clip(v - 1e-2 * np.sign(g[n]), 0, 100 if n == "throttle" else 325) for n, v in u.items()}
    assert s.robustness("AT1", s.simulate(step, t)) < rho


def test_a_suite_without_tangents_is_refused_with_a_value_error():
    s = hyfal.Suite("afc")  # ROS34PW2 with step-size control: no tangents
    t = np.array([0.0, 25.0, 50.0])
    with pytest.raises(ValueError, match="no gradients"):
        s.robustness_gradient("AFC27", {"u1": np.array([10.0, 60.0, 60.0])}, t)


def test_a_suite_searched_over_its_parameters_gives_their_slopes():
    # F16 is searched over its initial attitude (roll, pitch, yaw): grad keys them as floats.
    s = hyfal.Suite("f16")
    rho, g = s.robustness_gradient("F16", {}, [0.0, 15.0])
    assert set(g) == {"roll", "pitch", "yaw"}
    assert g["yaw"] == 0.0  # the altitude does not read the heading
    h = 1e-6
    for name, nominal in [("roll", np.pi / 4), ("pitch", -0.4 * np.pi)]:
        up = hyfal.Suite("f16", **{name: nominal + h})
        down = hyfal.Suite("f16", **{name: nominal - h})
        fd = (up.robustness("F16", up.simulate({}, [0.0, 15.0]))
              - down.robustness("F16", down.simulate({}, [0.0, 15.0]))) / (2 * h)
        assert g[name] == pytest.approx(fd, rel=1e-5), name

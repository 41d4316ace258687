"""Bad input raises a Python exception of the package's hierarchy with the command-line
tool's one-line message: what is wrong and where, with the likely name a typo meant."""

import pathlib

import numpy as np
import pytest

import mechanism


def test_the_exception_classes_form_one_hierarchy():
    for cls in (mechanism.DeclarationError, mechanism.InputError, mechanism.SolverError):
        assert issubclass(cls, mechanism.MechanismError)
    for cls in (mechanism.AssemblyError, mechanism.SingularError, mechanism.IntegrationError):
        assert issubclass(cls, mechanism.SolverError)


def test_every_builtin_name_is_a_file_of_mechanisms(root):
    files = sorted(p.stem for p in (root / "mechanisms").glob("*.mech"))
    assert sorted(mechanism.builtin_names()) == files


def test_an_unknown_mechanism_lists_the_names():
    with pytest.raises(mechanism.InputError) as e:
        mechanism.load("spatial_crank_slidr")
    assert str(e.value).startswith(
        "unknown mechanism `spatial_crank_slidr` (did you mean `spatial_crank_slider`?); "
        "available: spatial_crank_slider, ")
    assert "\n" not in str(e.value)


def test_a_declaration_error_names_file_line_and_column(tmp_path):
    bad = tmp_path / "bad.mech"
    bad.write_text("pub struct Bad;\ncoordinates { x = 0.0; }\nkinetic = 1/2*m*der(x)^2;\n")
    with pytest.raises(mechanism.DeclarationError, match=rf"^{bad}:3:15: unknown symbol `m`"):
        mechanism.load(str(bad))


def test_an_unknown_parameter_suggests_the_likely_one():
    seed = mechanism.load("spatial_crank_slider")
    with pytest.raises(mechanism.InputError, match=r"^set: unknown parameter `L2` \(did you mean `l2`\?\); parameters: h, l1, l2"):
        seed.simulate(set={"L2": 0.3})
    with pytest.raises(mechanism.InputError, match=r"^init: unknown coordinate `ph`"):
        seed.simulate(init={"ph": 0.1})


def test_an_impossible_body_is_refused_at_its_parameter():
    # The rigid rod's mass is declared `nonnegative`: a negative mass is refused at the
    # parameter, naming it and its declared range, as the CLI's --set does.
    with pytest.raises(mechanism.InputError, match=r"^set m2=-1: `m2` must be 0 or more \(its declaration says `nonnegative`\), got -1"):
        mechanism.load("spatial_crank_slider_rigid", set={"m2": -1.0})


def test_values_out_of_range_say_the_range():
    seed = mechanism.load("spatial_crank_slider")
    with pytest.raises(mechanism.InputError, match=r"^t_end must be > 0 s and at most 1e9 s, got 0"):
        seed.simulate(t_end=0.0)
    with pytest.raises(mechanism.InputError, match="integrator `rk5`: use one of rk4, dopri5, dop853, hht"):
        seed.simulate(integrator="rk5")
    with pytest.raises(mechanism.InputError, match="the value must be finite"):
        seed.simulate(set={"l2": float("nan")})


def test_wrong_shapes_and_frames_are_named():
    panda = mechanism.load("panda")
    with pytest.raises(mechanism.InputError, match=r"^q: expected 7 values \(one state\) or an array of shape \(rows, 7\), got shape \[6\]"):
        panda.mass_matrix(np.zeros(6))
    with pytest.raises(mechanism.InputError, match="^v: 3 rows while q has 2 rows"):
        panda.bias(np.zeros((2, 7)), np.zeros((3, 7)))
    with pytest.raises(mechanism.InputError, match=r"^q: entry 3 is NaN; states must be finite"):
        panda.mass_matrix([0, 0, 0, np.nan, 0, 0, 0])
    with pytest.raises(mechanism.InputError, match=r"^a: row 1, entry 2 is inf"):
        panda.inverse_dynamics(np.zeros((2, 7)), np.zeros((2, 7)), [[0] * 7, [0, 0, np.inf, 0, 0, 0, 0]])
    with pytest.raises(mechanism.InputError, match=r"^unknown frame `panda_hnd` \(did you mean `panda_hand`\?\)"):
        panda.frame_jacobian("panda_hnd", np.zeros(7))
    with pytest.raises(mechanism.InputError, match="declares no link frames"):
        mechanism.load("planar_four_bar").frame_jacobian("x", np.zeros(3))


def test_a_failed_assembly_raises_the_solver_message():
    four_bar = mechanism.load("planar_four_bar")
    # A loop that cannot close: the ground is longer than the three other bars together.
    with pytest.raises(mechanism.AssemblyError) as e:
        four_bar.simulate(t_end=0.1, set={"Dx": 10.0})
    assert "\n" not in str(e.value)


def test_a_lock_needs_a_urdf():
    with pytest.raises(mechanism.InputError, match="apply to a URDF file"):
        mechanism.load("panda", lock=["panda_joint1"])


def test_a_drive_of_an_unknown_coordinate_is_refused():
    seed = mechanism.load("spatial_crank_slider")
    with pytest.raises(mechanism.InputError, match="^drive: "):
        seed.inverse(["ph = 2*pi*t"])

"""The Whipple bicycle (mechanisms/whipple_bicycle.mech) linearised through Python at
forward speeds v = 0..10 m/s against Table 2 of Meijaard, Papadopoulos, Ruina and Schwab
(Proc. R. Soc. A 463, 2007), the values tests/nonholonomic/bicycle.rs holds the library to:
14 decimals printed, so 1e-10 leaves room for the round-off of a 10 x 10 eigenproblem and
none for a modelling error."""

import numpy as np
import pytest

import mechanism

TABLE_2 = [
    [-5.53094371765393, -3.13164324790656, 3.13164324790656, 5.53094371765393],
    [-7.11008014637442, -3.13423125066578, 3.52696170990070 - 0.8077402751993j,
     3.52696170990070 + 0.8077402751993j],
    [-8.67387984831735, -3.07158645641514, 2.68234517512745 - 1.68066296590675j,
     2.68234517512745 + 1.68066296590675j],
    [-10.3510146724592, -2.63366137253667, 1.70675605663975 - 2.31582447384325j,
     1.70675605663975 + 2.31582447384325j],
    [-12.1586142657645, -1.42944427361326, 0.41325331521125 - 3.07910818603206j,
     0.41325331521125 + 3.07910818603206j],
    [-14.0783896927982, -0.77534188219585 - 4.46486771378823j,
     -0.77534188219585 + 4.46486771378823j, -0.32286642900409],
    [-16.0853712309803, -1.52644486584142 - 5.87673060598709j,
     -1.52644486584142 + 5.87673060598709j, -0.00406690076970],
    [-18.15788466125262, -2.13875644258362 - 7.19525913329805j,
     -2.13875644258362 + 7.19525913329805j, 0.10268170574766],
    [-20.27940894394569, -2.69348683581097 - 8.46037971396931j,
     -2.69348683581097 + 8.46037971396931j, 0.14327879765713],
    [-22.43788559040858, -3.21675402252485 - 9.69377351531791j,
     -3.21675402252485 + 9.69377351531791j, 0.15790184030917],
    [-24.62459635017404, -3.72016840437287 - 10.90681139476287j,
     -3.72016840437287 + 10.90681139476287j, 0.16105338653172],
]


def ordered(values):
    return sorted(complex(v) for v in values)


def key(c):
    return (c.real, c.imag)


@pytest.fixture(scope="module")
def bicycle():
    return mechanism.load("whipple_bicycle")


@pytest.mark.parametrize("v", range(11))
def test_eigenvalues_match_table_2(bicycle, v):
    lin = bicycle.linearize(set={"v": float(v)})
    assert lin.structural_zeros == ["x", "y", "psi", "thR", "thF", "der(thR)"]
    assert lin.eigenvalues.dtype == np.complex128 and len(lin.eigenvalues) == 10
    ours = sorted((complex(c) for c in lin.reduced_eigenvalues), key=key)
    want = sorted((complex(c) for c in TABLE_2[v]), key=key)
    assert len(ours) == 4
    for o, w in zip(ours, want):
        assert abs(o.real - w.real) < 1e-10 and abs(o.imag - w.imag) < 1e-10, (v, o, w)
    # The state matrix's own eigenvalues are the ones reported.
    own = np.linalg.eigvals(lin.state_matrix)
    for c in lin.reduced_eigenvalues:
        assert np.abs(own - c).min() < 1e-9

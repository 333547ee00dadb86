#!/usr/bin/env python3
"""Reference eigenvalues of the circular plate (free and clamped edges) with mpmath.

Produces the 30-digit roots, printed to 16 significant digits, that the plate tests compare
the crate against:
  - tests/plates/modal_circular.rs, `free_eigenvalues_match_mpmath_roots_and_counting`
    (free edge, nu = 0.3 and nu = 0.33) and `clamped_eigenvalues_match_leissa_table`
    (its "mpmath roots to 1e-13 relative" rows);
  - tests/schemes/cli_lab.rs (free (2,0) at nu = 0.3, lambda^2 = 5.35833).

Equations (Leissa, "Vibration of Plates", NASA SP-160, 1969, eqs. 2.4 and 2.14), with
lambda^2 = omega a^2 sqrt(rho h / D) and the mode w = [J_n(lambda r) + C I_n(lambda r)] cos(n theta):
  clamped:  J_n(x) I_n'(x) - J_n'(x) I_n(x) = 0
  free:     P_J Q_I - P_I Q_J = 0, with (M_r = 0 and V_r = 0 at r = 1)
            P_J = x^2 J_n + (1-nu)(x J_n' - n^2 J_n),  P_I = x^2 I_n - (1-nu)(x I_n' - n^2 I_n),
            Q_J = x^3 J_n' + (1-nu) n^2 (x J_n' - J_n), Q_I = x^3 I_n' - (1-nu) n^2 (x I_n' - I_n).
Bessel functions and the root finder are mpmath's (independent of the crate's). Roots of order
n are found by a sign-change scan in steps of 0.05 from max(1, n/2) (which excludes the free
plate's rigid-body roots at 0), then refined with mpmath.findroot (Anderson) to 30 digits; the
label (n, k) is the order and the 0-based index of the root within that order, counting the free
plate's rigid-body root (lambda = 0, orders 0 and 1) as k = 0 as the crate does, so its first
elastic root of order 0 or 1 is (0,1) or (1,1).

Run:  python3 scripts/circular-plate-roots.py        (mpmath 1.3.0; about a second)
Output: one line per root, "edge nu (n,k) lambda^2", the values pasted into the tests above.
"""

import mpmath as mp

mp.mp.dps = 30


def characteristic(edge, nu, n, x):
    """The determinant whose zeros are the eigenvalues lambda (not lambda^2)."""
    j, dj = mp.besselj(n, x), mp.besselj(n, x, derivative=1)
    i, di = mp.besseli(n, x), mp.besseli(n, x, derivative=1)
    if edge == "clamped":
        return j * di - dj * i
    m, n2 = 1 - nu, n * n
    pj = x**2 * j + m * (x * dj - n2 * j)
    pi = x**2 * i - m * (x * di - n2 * i)
    qj = x**3 * dj + m * n2 * (x * dj - j)
    qi = x**3 * di - m * n2 * (x * di - i)
    # Scaled by e^{-x} (a positive factor) to keep the I_n terms of order one.
    return (pj * qi - pi * qj) * mp.exp(-x)


def root(edge, nu, n, k):
    """The root lambda labelled (n, k)."""
    if edge == "free" and n <= 1:
        k -= 1  # k = 0 is the rigid-body root at lambda = 0, not scanned
    a = max(mp.mpf(1), mp.mpf(n) / 2)
    step = mp.mpf("0.05")
    fa = characteristic(edge, nu, n, a)
    found = -1
    while True:
        b = a + step
        fb = characteristic(edge, nu, n, b)
        if mp.sign(fa) != mp.sign(fb):
            found += 1
            if found == k:
                return mp.findroot(lambda x: characteristic(edge, nu, n, x), (a, b), solver="anderson")
        a, fa = b, fb


TABLES = [
    ("free", "0.3", [(2, 0), (0, 1), (3, 0), (1, 1), (4, 0), (5, 0), (2, 1), (0, 2)]),
    ("free", "0.33", [(2, 0), (0, 1), (3, 0), (1, 1), (4, 0)]),
    ("clamped", "0.3", [(0, 0), (3, 0), (1, 2)]),
]

if __name__ == "__main__":
    print(f"# mpmath {mp.__version__}, {mp.mp.dps} digits; lambda^2 to 16 significant digits")
    for edge, nu, labels in TABLES:
        for n, k in labels:
            lam = root(edge, mp.mpf(nu), n, k)
            print(f"{edge} nu={nu} ({n},{k}) {mp.nstr(lam**2, 16)}")

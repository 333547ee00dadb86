#!/usr/bin/env python3
"""Linear frequencies of a free-edge shallow spherical shell, from the radial equations in
closed form (Bessel functions), with mpmath: a reference that shares no code with the crate.

Model: Donnell-Mushtari-Vlasov shallow shell over a circular base of radius a, thickness h,
radius of curvature R, written with the Airy stress function F as the curved von Karman plate
(Thomas, Touze & Chaigne, Int. J. Solids Struct. 42, 2005, eqs. 1-2, linear part):

    D lap^2 w + (1/R) lap F + rho h w_tt = 0,      lap^2 F - (E h / R) lap w = 0.

Units: a = 1, D = 1, rho h = 1, so omega = lambda^2 in units of sqrt(D / (rho h a^4)) (the flat
plate's lambda^2 of Leissa's tables), and with F~ = F / R only the product
mu = E h / (R^2 D) = 12 (1 - nu^2) kappa^2 enters, kappa = a^2 / (R h) the curvature parameter.
For a mode W(r) cos(n theta):

    lap F~ = mu W + C r^n   (C r^n cos(n theta) harmonic),
    lap^2 W - (lambda^4 - mu) W = -C r^n,

so W = A J_n(k r) + B I_n(k r) + C r^n / (lambda^4 - mu) with k^4 = lambda^4 - mu (for
lambda^4 < mu, k = |k| e^{i pi/4} and the real and imaginary parts of J_n(k r) are the real
basis), and F~ = -(mu/k^2) A J_n(kr) + (mu/k^2) B I_n(kr) + lambda^4/(lambda^4 - mu) C
r^{n+2} / (4(n+1)) + E r^n.

Free edge at r = 1 (Leissa, NASA SP-160, 1969, eq. 2.14 for the bending part; in-plane forces
N_r = N_rtheta = 0 from the stress function):
    M_r:  W'' + nu (W' - n^2 W) = 0
    V_r:  (lap_n W)' - (1 - nu) n^2 (W' - W) = 0
    N_r:  F' - n^2 F = 0
    N_rt: F' - F = 0                       (n >= 2; for n = 0 and 1 it is empty or N_r itself,
                                            and E drops out: three unknowns A, B, C)
The roots of the determinant in lambda are found by a sign-change scan and refined with
mpmath.findroot (Illinois, a bracketing method); a sign change at lambda^4 = mu (where the particular solution is singular)
is not a root and is skipped. At kappa = 0 the values are the flat free plate's
(scripts/circular-plate-roots.py), which this script checks first (to 1e-14). Checks of the
curved case: modes without nodal circles ((n, 0), n >= 2) barely move with kappa, modes with
nodal circles rise to the membrane limit lambda^2 = sqrt(mu) (Thomas, Touze & Chaigne 2005,
fig. 3), and the axisymmetric fundamental follows lambda^4 ~ lambda_plate^4 + mu (66.70 at
kappa = 20 against 66.70 from the flat plate's 9.0031). Limit: the one scan step that
straddles lambda^4 = mu (0.02 in lambda) is skipped, so a root inside it would be missed; a
printed root within two steps of lambda^4 = mu is flagged (kappa = 20 and 50: (0,1)), and the
crate's in-plane-exact route (core/src/modal/shell_condensed.rs, no shared code) finds the
same modes with the same labels, which a missed root would shift.

Run:  python3 scripts/shallow-shell-roots.py     (mpmath 1.3.0; about 40 s of CPU)
Output: for nu = 0.3 and kappa in KAPPAS, lambda^2 (15 significant digits) of the lowest
COUNTS[n] modes of each order n, labelled (n, k) as the crate labels the flat plate's modes
(k counts the rigid-body root of n = 0 and 1 as k = 0). The unit tests of
core/src/modal/shell_condensed_tests.rs copy these lines for kappa = 0, 5, 10, 20, 50.
"""

import mpmath as mp

mp.mp.dps = 30


def basis(n, lam4, mu):
    """Real basis pairs (W, F~) as functions of r returning (W, W', W'', lapW', F, F')."""
    k4 = lam4 - mu
    out = []
    if k4 > 0:
        k = mp.root(k4, 4)
        for kind in ("J", "I"):
            f = mp.besselj if kind == "J" else mp.besseli
            s = -1 if kind == "J" else 1  # lap_n of J_n(kr) is -k^2 J, of I_n(kr) is +k^2 I
            fac = s * mu / k**2

            def ev(r, f=f, s=s, fac=fac):
                z = k * r
                w0, w1, w2 = f(n, z), k * f(n, z, 1), k**2 * f(n, z, 2)
                lap1 = s * k**2 * w1
                return (w0, w1, w2, lap1, fac * w0, fac * w1)

            out.append(ev)
    else:
        k = mp.root(-k4, 4) * mp.expjpi(mp.mpf(1) / 4)
        fac = -mu / k**2

        def ev_c(r):
            z = k * r
            w0, w1, w2 = mp.besselj(n, z), k * mp.besselj(n, z, 1), k**2 * mp.besselj(n, z, 2)
            lap1 = -(k**2) * w1
            return (w0, w1, w2, lap1, fac * w0, fac * w1)

        out.append(lambda r: tuple(mp.re(x) for x in ev_c(r)))
        out.append(lambda r: tuple(mp.im(x) for x in ev_c(r)))

    # C r^n / (lam4 - mu) in W, with its F~ part; the harmonic r^n has lap_n = 0.
    cw = 1 / (lam4 - mu)
    cf = lam4 / (lam4 - mu) / (4 * (n + 1))

    def ev_p(r):
        w0 = cw * r**n
        w1 = cw * n * r ** (n - 1) if n >= 1 else mp.mpf(0)
        w2 = cw * n * (n - 1) * r ** (n - 2) if n >= 2 else mp.mpf(0)
        return (w0, w1, w2, mp.mpf(0), cf * r ** (n + 2), cf * (n + 2) * r ** (n + 1))

    out.append(ev_p)
    if n >= 2:
        out.append(lambda r: (0, 0, 0, 0, r**n, n * r ** (n - 1)))
    return out


def characteristic(n, lam, mu, nu):
    lam4 = lam**4
    rows = []
    for ev in basis(n, lam4, mu):
        w0, w1, w2, lap1, f0, f1 = ev(mp.mpf(1))
        col = [w2 + nu * (w1 - n * n * w0), lap1 - (1 - nu) * n * n * (w1 - w0)]
        if n == 0:
            col.append(f1)
        elif n == 1:
            col.append(f1 - f0)
        else:
            col += [f1 - n * n * f0, f1 - f0]
        rows.append(col)
    m = mp.matrix(rows).T
    # Columns scaled to unit norm: the I_n column grows like e^k.
    for j in range(m.cols):
        s = mp.sqrt(sum(m[i, j] ** 2 for i in range(m.rows)))
        if s != 0:
            for i in range(m.rows):
                m[i, j] /= s
    return mp.det(m)


def roots(n, mu, nu, count, lam_max=40):
    """The lowest `count` elastic roots lambda (> 0) of order n."""
    found = []
    step = mp.mpf("0.02")
    a = mp.mpf("0.3")
    fa = characteristic(n, a, mu, nu)
    while len(found) < count and a < lam_max:
        b = a + step
        fb = characteristic(n, b, mu, nu)
        singular = (a**4 - mu) * (b**4 - mu) <= 0
        if mp.sign(fa) != mp.sign(fb) and not singular:
            r = mp.findroot(lambda x: characteristic(n, x, mu, nu), (a, b), solver="illinois")
            found.append(r)
        a, fa = b, fb
    return found


FLAT_CHECK = {  # nu = 0.3, from scripts/circular-plate-roots.py (lambda^2, 16 digits)
    (2, 0): "5.358329787899912",
    (0, 1): "9.003137350295527",
    (3, 0): "12.43898816540814",
    (1, 1): "20.47455011393814",
    (2, 1): "35.26010831537333",
    (0, 2): "38.44319824475232",
}

KAPPAS = [0, 1, 2, 5, 10, 20, 50]
# Roots printed per order n: (0,1)-(0,3), (1,1)-(1,2), (2,0)-(2,1), (3,0)-(3,1), (4,0)-(4,1).
COUNTS = {0: 3, 1: 2, 2: 2, 3: 2, 4: 2}

if __name__ == "__main__":
    nu = mp.mpf("0.3")
    print(f"# mpmath {mp.__version__}, {mp.mp.dps} digits; nu = 0.3; lambda^2 = omega a^2 sqrt(rho h / D)")
    for (n, k), want in FLAT_CHECK.items():
        index = k - 1 if n <= 1 else k  # the rigid-body root (n <= 1, k = 0) is not scanned
        got = roots(n, 0, nu, index + 1)[index] ** 2
        assert abs(got / mp.mpf(want) - 1) < 1e-14, (n, k, got, want)
    print("# flat limit (kappa = 0) matches the free plate's roots to 1e-14")
    for kappa in KAPPAS:
        mu = 12 * (1 - nu**2) * mp.mpf(kappa) ** 2
        for n, count in COUNTS.items():
            first = 1 if n <= 1 else 0
            for j, lam in enumerate(roots(n, mu, nu, count)):
                # Distance from the skipped step (lambda^4 = mu), in scan steps: a root within
                # about one step of it could have a neighbour that the scan missed.
                gap = abs(lam - mp.root(mu, 4)) / mp.mpf("0.02") if mu > 0 else mp.inf
                flag = "" if gap > 2 else f"   # {mp.nstr(gap, 3)} steps from lambda^4 = mu"
                print(f"kappa={kappa} ({n},{j + first}) {mp.nstr(lam**2, 15)}{flag}")

#!/usr/bin/env python3
"""Directional albedo of coated diffuse (pbrt-v4 coateddiffuse as restir-lab's closed form,
src/scene/bsdf_coated.h; Mitsuba 3's plastic / roughplastic with nonlinear = true) at theta_o, by
quadrature: the expected pixel value of scripts/mitsuba-cases/plane-coated*.pbrt (a plane under a
constant white environment seen at theta_o, max depth 1).

  albedo = E_spec(mu_o) + T(mu_o) R Tbar / (eta^2 (1 - R Fdr)),   Tbar = 2 ∫ T(mu) mu dmu

restir-lab: height-correlated Smith G2, T and Fdr by (fine) quadrature; the smooth coat's Fdr in
closed form (Walsh's Fresnel integral). Mitsuba 3: separable G1 G1 (and G1(wt) in T); T tabulated on
64 uniform nodes in mu and interpolated linearly; Fdr = 2 mean_j(E_int(mu_j) mu_j) over the same
nodes (roughplastic.cpp); a smooth coat's Fdr from the Egan-Hilgeman fit (fresnel.h).
Usage: coated_albedo.py ALPHA ETA R [THETA_O_DEG]   (ALPHA 0 = smooth coat; R one value or r,g,b)"""
import sys
import numpy as np

alpha, eta = float(sys.argv[1]), float(sys.argv[2])
R = np.array([float(v) for v in sys.argv[3].split(",")])
R = np.repeat(R, 3) if R.size == 1 else R
mu_o = np.cos(np.radians(float(sys.argv[4]) if len(sys.argv) > 4 else 60.0))
LUM = np.array([0.2126, 0.7152, 0.0722])


def fresnel(c, n):  # dielectric, unpolarized; c = cos on the side of relative index n; TIR -> 1
    c = np.clip(c, 1e-12, 1)
    s2t = (1 - c * c) / (n * n)
    ct = np.sqrt(np.maximum(1 - s2t, 0))
    rp = (n * c - ct) / (n * c + ct)
    rs = (c - n * ct) / (c + n * ct)
    return np.where(s2t >= 1, 1.0, 0.5 * (rp * rp + rs * rs))


def lam(cos):
    t2 = np.maximum(1 - cos**2, 0) / np.maximum(cos**2, 1e-30)
    return 0.5 * (np.sqrt(1 + alpha**2 * t2) - 1)


# Microfacet normals on a fine grid (theta_m, phi_m), with their solid angle.
n_t, n_p = 800, 400
tm = (np.arange(n_t) + 0.5) / n_t * np.pi / 2
pm = (np.arange(n_p) + 0.5) / n_p * 2 * np.pi
TM, PM = np.meshgrid(tm, pm, indexing="ij")
M = np.stack([np.sin(TM) * np.cos(PM), np.sin(TM) * np.sin(PM), np.cos(TM)], -1)
dwm = np.sin(TM) * (np.pi / 2 / n_t) * (2 * np.pi / n_p)
D = 1 / (np.pi * alpha**2 * ((M[..., 0]**2 + M[..., 1]**2) / alpha**2 + M[..., 2]**2)**2) if alpha > 0 else None


def lobe(mu, n, transmit, separable):
    """∫ D_w(m) F-or-(1-F) G/G1(w) dm for w at cos mu: reflection or (energy) transmission albedo."""
    w = np.array([np.sqrt(1 - mu * mu), 0, mu])
    wm = M @ w
    F = fresnel(wm, n)
    if transmit:  # refraction into the other side (Snell, relative index n)
        ct = np.sqrt(np.maximum(1 - (1 - wm**2) / n**2, 0))
        wo = -w[None, None, :] / n + (wm / n - ct)[..., None] * M
        ok, weight = (wo[..., 2] < 0) & (F < 1), 1 - F
    else:
        wo = 2 * wm[..., None] * M - w
        ok, weight = wo[..., 2] > 0, F
    G = 1 / (1 + lam(mu)) / (1 + lam(np.abs(wo[..., 2]))) if separable else 1 / (1 + lam(mu) + lam(np.abs(wo[..., 2])))
    # D_w(m) = G1(w) (w.m) D(m) / mu (Heitz 2018 eq. 2) times the weight G / G1(w): G1 cancels.
    with np.errstate(invalid="ignore", divide="ignore"):
        return float(np.sum(np.where(ok & (wm > 0), wm * D * weight * G / mu, 0) * dwm))


def walsh(n):  # 2 ∫ F(mu, n) mu dmu, n > 1 (Walsh 1926)
    n2, n4 = n * n, n**4
    return (0.5 + (n - 1) * (3 * n + 1) / (6 * (n + 1)**2) + n2 * (n2 - 1)**2 / (n2 + 1)**3 * np.log((n - 1) / (n + 1))
            - 2 * n**3 * (n2 + 2 * n - 1) / ((n2 + 1) * (n4 - 1)) + 8 * n4 * (n4 + 1) / ((n2 + 1) * (n4 - 1)**2) * np.log(n))


def gl(f, n=48):  # 2 ∫_0^1 f(mu) mu dmu, Gauss-Legendre
    x, w = np.polynomial.legendre.leggauss(n)
    x, w = 0.5 * (x + 1), 0.5 * w
    return 2 * sum(wi * f(xi) * xi for xi, wi in zip(x, w))


def albedo(e_spec, t_o, tbar, fdr):
    return e_spec + t_o * R * tbar / (eta**2 * (1 - R * fdr))


if alpha == 0:
    f_o, ext = float(fresnel(mu_o, eta)), walsh(eta)
    fdr_exact = 1 - (1 - ext) / eta**2
    ie = 1 / eta  # Mitsuba: fresnel_diffuse_reflectance(1 / eta), the Egan-Hilgeman fit for eta < 1
    fdr_fit = 0.0636 * (1 / ie) + ie * (ie * -1.4399 + 0.7099) + 0.6681
    a_r, a_m = albedo(f_o, 1 - f_o, 1 - ext, fdr_exact), albedo(f_o, 1 - f_o, 1 - ext, fdr_fit)
    print(f"smooth coat eta {eta}: Fdr_int {fdr_exact:.5f} (Mitsuba's fit {fdr_fit:.5f})")
else:
    T = lambda mu, sep: lobe(max(mu, 1e-4), eta, True, sep)
    fdr_r = gl(lambda mu: lobe(max(mu, 1e-4), 1 / eta, False, False))
    a_r = albedo(lobe(mu_o, eta, False, False), T(mu_o, False), gl(lambda mu: T(mu, False)), fdr_r)
    nodes = np.maximum(1e-6, np.linspace(0, 1, 64))
    tab = np.array([T(mu, True) for mu in nodes])
    t_m = lambda mu: float(np.interp(mu, np.linspace(0, 1, 64), tab))
    fdr_m = 2 * np.mean([lobe(mu, 1 / eta, False, True) * mu for mu in nodes])
    a_m = albedo(lobe(mu_o, eta, False, True), t_m(mu_o), gl(t_m, 96), fdr_m)
    print(f"rough coat alpha {alpha} eta {eta}: Fdr {fdr_r:.5f} (Mitsuba {fdr_m:.5f}), T(mu_o) {T(mu_o, False):.5f} "
          f"(Mitsuba {t_m(mu_o):.5f})")
print(f"R {R}, theta_o {np.degrees(np.arccos(mu_o)):.0f} deg: albedo restir-lab {a_r} -> luminance {a_r @ LUM:.5f}; "
      f"Mitsuba 3 {a_m} -> luminance {a_m @ LUM:.5f}")

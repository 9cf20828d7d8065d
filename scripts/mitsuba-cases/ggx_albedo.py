#!/usr/bin/env python3
"""Directional albedo of a GGX conductor (F from eta = 1, k = 2 sqrt(r / (1 - r)), r = 0.9999) at
theta_o, by quadrature over wi, with the two Smith masking-shadowing forms in use:
height-correlated G2 = 1 / (1 + L(wo) + L(wi)) (pbrt-v4, restir-lab) and separable
G1(wo) G1(wi) (Mitsuba 3). The expected pixel value of scripts/mitsuba-cases/plane-rough-conductor-*.
Usage: ggx_albedo.py ALPHA [THETA_O_DEG]"""
import sys
import numpy as np

alpha = float(sys.argv[1])
theta_o = np.radians(float(sys.argv[2]) if len(sys.argv) > 2 else 60.0)
r = 0.9999
k = 2 * np.sqrt(r / (1 - r))


def fresnel(c):  # exact conductor Fresnel, eta = 1 + i k, from vacuum
    eta = complex(1, k)
    s2 = 1 - c * c
    ct = np.sqrt(1 - s2 / eta**2 + 0j)
    rs = (c - eta * ct) / (c + eta * ct)
    rp = (eta * c - ct) / (eta * c + ct)
    return 0.5 * (abs(rs)**2 + abs(rp)**2)


def lam(cos):
    t2 = (1 - cos**2) / cos**2
    return 0.5 * (np.sqrt(1 + alpha**2 * t2) - 1)


n_t, n_p = 4000, 2000
th = (np.arange(n_t) + 0.5) / n_t * np.pi / 2
ph = (np.arange(n_p) + 0.5) / n_p * 2 * np.pi
T, P = np.meshgrid(th, ph, indexing="ij")
wi = np.stack([np.sin(T) * np.cos(P), np.sin(T) * np.sin(P), np.cos(T)], -1)
wo = np.array([np.sin(theta_o), 0, np.cos(theta_o)])
h = wi + wo
h /= np.linalg.norm(h, axis=-1, keepdims=True)
D = 1 / (np.pi * alpha**2 * ((h[..., 0]**2 + h[..., 1]**2) / alpha**2 + h[..., 2]**2)**2)
F = fresnel(np.sum(h * wo, -1))
ci, co = wi[..., 2], wo[2]
dw = np.sin(T) * (np.pi / 2 / n_t) * (2 * np.pi / n_p)
for name, G in (("height-correlated (restir-lab, pbrt-v4)", 1 / (1 + lam(co) + lam(ci))),
                ("separable (Mitsuba 3)", 1 / (1 + lam(co)) / (1 + lam(ci)))):
    print(f"alpha {alpha}, theta_o {np.degrees(theta_o):.0f} deg, G {name}: albedo {np.sum(D * G * F / (4 * co) * dw):.5f}")

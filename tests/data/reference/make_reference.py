#!/usr/bin/env python3
# 80-digit reference for the example assembly's SH11 and SHT11 (tests/assembly_test.cpp,
# Assembly.AccuracyAgainstAnEightyDigitReference). Needs mpmath (not needed by the tests).
#
# Input: example_model.txt, the example's chains as AssemblyModel builds them (the test checks
# that it still does): per chain its pieces "piece L EI.re EI.im kGA.re kGA.im rhoA rhoI" from
# end 1 (SI units), its ground springs per node "ground node count k c k_theta c_theta", and the
# joints "joint name rigid k_yf c_yf k_ym c_ym k_tf c_tf k_tm c_tm".
# Output (stdout): JSON with the frequencies [Hz] and, per frequency, SH11 and SHT11 as
# [H, L, N, P] pairs [re, im] (m/N, 1/N, rad/N, rad/(N m)) to 20 significant digits.
#
# The algebra is the library's, carried out in 80-digit arithmetic: the free-free Timoshenko end
# receptances from the closed form (src/beam.cpp; the quadratic's roots taken directly here), the
# spindle walked from its rear end with the bearings by structural modification (Chain::point),
# the holder and tool coupled rigidly into two-ports (Chain::two_port), then Eq. 1 and Eq. 5.
# What it checks is rounding: at low frequency the coupling subtracts free-free receptances far
# larger than the result, and 80 digits make that cancellation harmless.
import json, sys
import mpmath as mp

mp.mp.dps = 80
FREQUENCIES = ["1", "3", "10", "13", "30", "100", "300", "1000", "3000", "10000", "50000"]

chains, joints, cur = {}, {}, None
for line in open(sys.argv[1] if len(sys.argv) > 1 else "example_model.txt"):
    t = line.split()
    if not t:
        continue
    if t[0] == "chain":
        cur = chains[t[1]] = {"pieces": [], "grounds": []}
    elif t[0] == "piece":
        cur["pieces"].append([mp.mpf(x) for x in t[1:]])
    elif t[0] == "ground":
        cur["grounds"].append((int(t[2]), [mp.mpf(x) for x in t[3:]]))
    elif t[0] == "joint":
        joints[t[1]] = (int(t[2]), [mp.mpf(x) for x in t[3:]])


def mm(x, y):
    return [[x[i][0] * y[0][j] + x[i][1] * y[1][j] for j in range(2)] for i in range(2)]


def add(x, y):
    return [[x[i][j] + y[i][j] for j in range(2)] for i in range(2)]


def sub(x, y):
    return [[x[i][j] - y[i][j] for j in range(2)] for i in range(2)]


def inv(x):
    d = x[0][0] * x[1][1] - x[0][1] * x[1][0]
    return [[x[1][1] / d, -x[0][1] / d], [-x[1][0] / d, x[0][0] / d]]


I2 = [[mp.mpc(1), mp.mpc(0)], [mp.mpc(0), mp.mpc(1)]]


def segment(piece, w2):
    """Free-free end blocks (T11, T12, T21, T22) of one piece (beam.cpp's closed form)."""
    L, EIr, EIi, kr, ki, mA, mI = piece
    a, b = mp.mpc(kr, ki), mp.mpc(EIr, EIi)
    B = (a * mI + b * mA) * w2
    C = mA * w2 * (a - mI * w2)
    disc = mp.sqrt(B * B + 4 * a * b * C)
    p = [(-B - disc) / (2 * a * b), (-B + disc) / (2 * a * b)]
    s = [mp.sqrt(x) for x in p]
    e = [a * x + mA * w2 for x in p]
    c, pS, S = [], [], []
    for j in range(2):
        m1 = mp.exp(-s[j] * L) - 1
        c.append(1 + m1 / 2)
        sig = -m1 / 2
        pS.append(sig * s[j])
        S.append(sig / s[j] if s[j] != 0 else L / 2)
    de, u = e[1] - e[0], -a * mA * w2
    P, Q, U, V = c[0] * pS[1], c[1] * pS[0], c[1] * S[0], c[0] * S[1]
    ds, da = e[1] * P - e[0] * Q, e[1] * U - e[0] * V
    f_a, a_over_b, f_d = a / u * de, a / b, de / b
    ga_s, ga_a = f_a / ds * pS[0] * pS[1], f_a / da * c[0] * c[1]
    gb_s, gb_a = a_over_b / ds * (P - Q), a_over_b / da * (U - V)
    gd_s, gd_a = f_d / ds * c[0] * c[1], f_d / da * S[0] * S[1]
    h, l, pp = (ga_s + ga_a) / 2, (gb_s + gb_a) / 2, (gd_s + gd_a) / 2
    h12, l12, p12 = (ga_a - ga_s) / 2, (gb_s - gb_a) / 2, (gd_s - gd_a) / 2
    return ([[h, l], [l, pp]], [[h12, l12], [-l12, p12]], [[h12, -l12], [l12, p12]], [[h, -l], [-l, pp]])


def ground(g, w):
    _, (k, c, kt, ct) = g
    return [[mp.mpc(k, w * c), mp.mpc(0)], [mp.mpc(0), mp.mpc(kt, w * ct)]]


def chain_point(ch, w, w2):
    P, G, n = ch["pieces"], ch["grounds"], len(ch["pieces"])
    T = segment(P[n - 1], w2)
    g = T[0]
    if G[n][0] > 0:
        D = ground(G[n], w)
        g = sub(T[0], mm(mm(T[1], mm(D, inv(add(I2, mm(T[3], D))))), T[2]))
    for k in range(n - 2, -1, -1):
        if G[k + 1][0] > 0:
            g = mm(g, inv(add(I2, mm(ground(G[k + 1], w), g))))
        T = segment(P[k], w2)
        g = sub(T[0], mm(mm(T[1], inv(add(T[3], g))), T[2]))
    if G[0][0] > 0:
        g = mm(g, inv(add(I2, mm(ground(G[0], w), g))))
    return g


def chain_two_port(ch, w2):
    assert all(g[0] == 0 for g in ch["grounds"])
    P, n = ch["pieces"], len(ch["pieces"])
    g = segment(P[n - 1], w2)
    for k in range(n - 2, -1, -1):
        a = segment(P[k], w2)
        X = inv(add(a[3], g[0]))
        xa21, xb12 = mm(X, a[2]), mm(X, g[1])
        g = (sub(a[0], mm(a[1], xa21)), mm(a[1], xb12), mm(g[2], xa21), sub(g[3], mm(g[2], xb12)))
    return g


def couple_point(t, b11, joint, w):
    rigid, p = joint
    if rigid:
        X = inv(add(t[3], b11))
    else:
        K = [[mp.mpc(p[0], w * p[1]), mp.mpc(p[2], w * p[3])], [mp.mpc(p[4], w * p[5]), mp.mpc(p[6], w * p[7])]]
        X = mm(K, inv(add(I2, mm(add(t[3], b11), K))))
    return sub(t[0], mm(mm(t[1], X), t[2]))


def entries(b):
    return [[mp.nstr(v.real, 20), mp.nstr(v.imag, 20)] for v in (b[0][0], b[0][1], b[1][0], b[1][1])]


out = {"frequency_hz": [], "SH11": [], "SHT11": []}
for fs in FREQUENCIES:
    w = 2 * mp.pi * mp.mpf(fs)
    w2 = w * w
    sh = couple_point(chain_two_port(chains["holder"], w2), chain_point(chains["spindle"], w, w2), joints["sh"], w)
    sht = couple_point(chain_two_port(chains["tool"], w2), sh, joints["ht"], w)
    out["frequency_hz"].append(float(fs))
    out["SH11"].append(entries(sh))
    out["SHT11"].append(entries(sht))
json.dump(out, sys.stdout, indent=1)
print()

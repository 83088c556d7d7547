"""Write the example's measured curves: what a direct-shear box would give for a geotextile on sand.

They are synthetic, so that the example's answer is known: the softening law (peak, then a linear
fall of strength to the residual over a plastic slip) with Ks = 18 000 kPa/m, c = 12 kPa, φ = 31°,
c_r = 6 kPa, φ_r = 23°, softening slip 8 mm, at σn = 25, 50 and 100 kPa, the slip to 20 mm every
0.25 mm, each value off by a relative error of standard deviation 2 % (seed 3). Plain Python, no
geoslip: python3 make_curves.py > direct-shear.csv
"""

import math
import random

KS, C, PHI, CR, PHIR, SOFT = 18000.0, 12.0, 31.0, 6.0, 23.0, 0.008


def tau(slip, sigma):
    tp = C + sigma * math.tan(math.radians(PHI))
    tr = CR + sigma * math.tan(math.radians(PHIR))
    if KS * slip <= tp:
        return KS * slip
    h = (tp - tr) / SOFT  # strength lost per unit plastic slip
    t = (tp - h * slip) / (1 - h / KS)  # on the softening branch, slip = plastic + t/Ks
    return max(t, tr) if slip - t / KS < SOFT else tr


random.seed(3)
print("# synthetic direct-shear curves (make_curves.py): softening law, 2 % noise")
print("normal_stress [kPa],slip [mm],shear_stress [kPa]")
for sigma in (25.0, 50.0, 100.0):
    for k in range(81):
        slip = 0.25e-3 * k
        print(f"{sigma},{1e3 * slip:.2f},{tau(slip, sigma) * (1 + 0.02 * random.gauss(0, 1)):.3f}")

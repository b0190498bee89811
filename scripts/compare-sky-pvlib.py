#!/usr/bin/env python3
"""The built-in sky against pvlib's clear-sky models (docs/model.md §3.12).

For turbidity 2, 3, 6 and a sun 15°, 30°, 50°, 70° high, `diffract gen sky` prints what a horizontal surface gets
from the sun and from the sky (klx); pvlib's Ineichen–Perez (Linke turbidity = the turbidity), Haurwitz and
simplified Solis (aerosol optical depth 0.1 up to turbidity 3, else 0.3; 1 cm of water) give the global horizontal
irradiance (W/m²), turned into illuminance with a daylight efficacy of 105–115 lm/W. A case is inside where
diffract's sun + sky lies between the lowest model × 105 and the highest × 115.

pvlib is a peer for this check, never a dependency of diffract: `pip install pvlib pandas`, then
`python3 scripts/compare-sky-pvlib.py [--sky-model preetham]` from the repository (after `cargo build --release`).
Measured 2026-11-28 (d4817a9): Hosek–Wilkie 12 of 12 inside; Preetham's sky 2 of 12 (above in 10).
"""
import re
import subprocess
import sys
import tempfile

import pandas as pd
import pvlib

BINARY = "target/release/diffract"
model = sys.argv[sys.argv.index("--sky-model") + 1] if "--sky-model" in sys.argv else "hosek-wilkie"
inside = total = 0
with tempfile.TemporaryDirectory() as scratch:
    for turbidity in [2, 3, 6]:
        for elevation in [15, 30, 50, 70]:
            out = subprocess.run(
                [BINARY, "gen", "sky", "--width", "64", "--sun-elevation-deg", str(elevation), "--turbidity",
                 str(turbidity), "--sky-model", model, "--out", f"{scratch}/sky.exr"],
                capture_output=True, text=True, check=True).stdout
            m = re.search(r"gets ([0-9.]+) klx from the sun and ([0-9.]+) klx from the sky", out)
            ours = float(m.group(1)) + float(m.group(2))
            zenith = 90 - elevation
            airmass = pvlib.atmosphere.get_absolute_airmass(pvlib.atmosphere.get_relative_airmass(zenith))
            ghi = [
                float(pvlib.clearsky.ineichen(zenith, airmass, turbidity, dni_extra=1361.0)["ghi"]),
                float(pvlib.clearsky.haurwitz(pd.Series([zenith]))["ghi"].iloc[0]),
                float(pvlib.clearsky.simplified_solis(elevation, aod700=0.1 if turbidity <= 3 else 0.3,
                                                      precipitable_water=1.0, dni_extra=1361.0)["ghi"]),
            ]
            lo, hi = min(ghi) * 0.105, max(ghi) * 0.115
            where = "inside" if lo <= ours <= hi else ("above" if ours > hi else "below")
            inside += where == "inside"
            total += 1
            print(f"turbidity {turbidity}, sun {elevation}°: diffract {ours:.1f} klx; pvlib GHI "
                  f"{ghi[0]:.0f} / {ghi[1]:.0f} / {ghi[2]:.0f} W/m² -> {lo:.1f}–{hi:.1f} klx: {where}")
print(f"{model}: {inside} of {total} inside the clear-sky models' spread")

"""Issue 10 §5: the paper's §4 procedure run literally, beside ours (prints its figures; not a test).

Usage (from the repository root)::

    peenflow run studies/paper_literal.toml --workers 2 --threads 1 --until target_velocity
    peenflow run studies/paper_fast_extrapolated.toml --workers 2 --threads 1
    python benchmarks/literal.py

The literal study peens the paper's strip REV (6D x 6D, symmetric lateral faces, 2D x 2D
measuring region) through the paper's ladder N = 10 ... 480, fits eq. (10) to those rungs and
solves eq. (11) wherever it lands, at 40 um (its coarse level, the strips of
studies/paper_literal_40um.toml) and at 25 um (the paper's mesh), with the same shot streams.
Ours (studies/paper_fast_extrapolated.toml) peens a periodic 1.2 mm REV measured over its whole
face through a ladder that extends itself until eq. (11)'s saturation point T has a rung at >= 2 T,
at 40 and 25 um. Printed, on the 67.5 deg curve (the paper's 12A curve): per literal level and
velocity the intensity, its spread over sequences, T against the last rung (480) and the mean arc
height at 480 shots; every curve side by side (the literal levels, the literal curve extrapolated
to zero element size from its mean-curve intensities and as the study's paired stage does it, our
levels and ours extrapolated); the velocity for 12A (0.30 mm) of each (PCHIP inverse, as the
target_velocity stage; for a curve wholly above 0.30 mm also where the line through its two
lowest points reaches it), the converged reference's (docs/validation.md section 9) and the paper's 47 m/s.
"""

from __future__ import annotations

import argparse
from pathlib import Path

import numpy as np

from peenflow.validation.study_level import INTENSITY_12A_MM, stage_results, study_level_errors, velocity_12a

ROOT = Path(__file__).resolve().parents[1]

LITERAL_25 = ROOT / "studies" / "paper_literal.toml"  # its coarse level is paper_literal_40um.toml
OURS = ROOT / "studies" / "paper_fast_extrapolated.toml"
ANGLE_DEG = 67.5
PAPER_12A_M_S = 47.0
LITERAL_LAST_RUNG = 480


def _at_angle(ds, var: str):
    """``ds[var]`` at 67.5 deg (a study with one angle may have no angle dimension left)."""
    return ds[var].sel(angle_deg=ANGLE_DEG) if "angle_deg" in ds[var].dims else ds[var]


def _by_velocity(ds, var: str, scale: float = 1.0) -> dict[float, float]:
    """{velocity m/s: value * scale} of ``var`` on the 67.5 deg points of a saturation-like Dataset."""
    da = _at_angle(ds, var)
    return {float(v): float(x) * scale for v, x in zip(np.asarray(da.velocity_m_s), np.asarray(da, float))}


def _curve(ds) -> dict[float, float]:
    """{velocity m/s: intensity mm} of the 67.5 deg points."""
    return _by_velocity(ds, "intensity_m", 1e3)


def _v12a(curve: dict[float, float]) -> str:
    """The 12A velocity of the curve (PCHIP inverse); for a curve wholly above 0.30 mm, also where the
    straight line through its two lowest-velocity points reaches it (an extension below the curve)."""
    try:
        return f"{velocity_12a(curve):.2f}"
    except ValueError:  # 0.30 mm outside the curve
        if min(curve.values()) <= INTENSITY_12A_MM:
            return f"above {max(curve):g} (out of the curve)"
        (v0, i0), (v1, i1) = sorted(curve.items())[:2]
        line = v0 + (INTENSITY_12A_MM - i0) * (v1 - v0) / (i1 - i0)
        return (f"below {min(curve):g} (out of the curve); the line through its two lowest points reaches "
                f"0.30 mm at {line:.1f}")


def _literal_table(lit) -> dict[str, dict[float, float]]:
    """Per velocity: the literal level's intensity, its saturation point T, the mean arc height at the
    last rung, the spread over sequences (mm) and the number of sequences."""
    return {"I": _curve(lit), "T": _by_velocity(lit, "saturation_shots"),
            "Ah_last": {v: float(x) * 1e3 for v, x in zip(np.asarray(lit.velocity_m_s), np.asarray(
                _at_angle(lit, "mean_arc_height_m").sel(shots=LITERAL_LAST_RUNG)))},
            "spread": _by_velocity(lit, "intensity_std_m", 1e3),
            "n": {float(v): int(c) for v, c in zip(np.asarray(lit.velocity_m_s),
                                                   np.asarray(_at_angle(lit, "sequence_intensity_m").count("sequence")))}}


def main() -> None:
    lit40, lit25, lit_ext = stage_results(LITERAL_25, "coarse_saturation", "saturation", "intensity_extrapolation")
    ext, fine, coarse = stage_results(OURS, "intensity_extrapolation", "saturation", "coarse_saturation")
    tables = {"40 um": _literal_table(lit40), "25 um": _literal_table(lit25)}
    k = float(lit_ext.attrs["extrapolation_factor"])
    # the extrapolation of the mean-curve intensities (the study's own is paired per sequence, and a
    # sequence whose eq. (11) lands far beyond its ladder makes that pairing meaningless: printed too)
    lit_mean_ext = {v: tables["25 um"]["I"][v] + k * (tables["25 um"]["I"][v] - tables["40 um"]["I"][v])
                    for v in tables["25 um"]["I"]}
    curves = {"literal 40 um": tables["40 um"]["I"], "literal 25 um": tables["25 um"]["I"],
              "literal extrapolated (mean curves)": lit_mean_ext,
              "literal extrapolated (study, paired)": _curve(lit_ext),
              "ours 40 um": _curve(coarse), "ours 25 um": _curve(fine), "ours extrapolated": _curve(ext)}
    refs = study_level_errors()["reference"]
    ref_v = refs["velocity_12a_m_s"]

    print(f"67.5 deg control curve (literal: 6D x 6D REV, symmetric faces, 2D x 2D measuring region, "
          f"N <= {LITERAL_LAST_RUNG}, eq. (11) wherever it lands; ours: periodic 1.2 mm REV over its whole face, "
          "saturated inside its ladder); intensities mm\n")
    for level, t in tables.items():
        print(f"literal, {level}:")
        print("| velocity m/s | intensity (seq., spread) | T shots | Ah(480) mm |")
        print("|---|---|---|---|")
        for v in sorted(t["I"]):
            print(f"| {v:g} | {t['I'][v]:.4f} ({t['n'][v]}, ± {t['spread'][v]:.4f}) | {t['T'][v]:.0f} | "
                  f"{t['Ah_last'][v]:.4f} |")
        print()
    names = list(curves)
    print("| velocity m/s | " + " | ".join(names) + " |")
    print("|---|" + "---|" * len(names))
    for v in sorted(lit_mean_ext):
        print(f"| {v:g} | " + " | ".join(f"{curves[n].get(v, float('nan')):.4f}" for n in names) + " |")
    print("\nvelocity for 12A (0.30 mm), m/s:")
    for name, c in curves.items():
        print(f"  {name}: {_v12a(c)}")
    print(f"  converged reference: {ref_v:.2f}\n  paper: {PAPER_12A_M_S:g}")


if __name__ == "__main__":
    argparse.ArgumentParser(description=__doc__.split("\n\n")[0]).parse_args()
    main()

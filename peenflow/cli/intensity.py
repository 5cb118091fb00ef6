"""The Almen intensity of measured strips (a CSV of exposures and arc heights), SAE J2597 style.

Fits the paper's eq. (10) and SAE J2597's two- and three-parameter
exponentials, judges each (residual, parameters on a bound, whether the
saturation point T is bracketed by strips), and reports one. Exit status 0: the
reported fit passes every check; 1: no fit does (the intensity is printed but
is extrapolated or rests on a fit at a bound); 2: the file cannot be used.
"""

from __future__ import annotations

from pathlib import Path

from ..methods.measured_strips import MODELS
from tasks.measured_intensity import almen_strips_intensity

from ..study.almen_strips import AlmenStripsError, read_almen_strips, shop_notation, strip_types
from ._common import UserError

NAME = "intensity"
HELP = "Almen intensity of measured strips (CSV of exposures and arc heights)"


def add_arguments(p) -> None:
    p.add_argument("csv", help="strips: a header naming the exposure (time_min, passes, shots or coverage_percent) "
                               "and the arc height with its unit (arc_height_mm, arc_height_in or arc_height_thou); "
                               "one row per strip; # starts a comment line")
    p.add_argument("--strip", required=True, metavar="TYPE",
                   help="Almen strip type, N, A or C (the packaged strip library): the letter of the shop notation")


def _mm(x_m: float) -> str:
    return f"{x_m * 1e3:.4f} mm"


def main(args) -> int:
    types = strip_types()
    strip = args.strip.strip().upper()
    if strip not in types:
        raise UserError(f"--strip {args.strip!r}: expected one of {', '.join(types)} (the strip library's types)")
    path = Path(args.csv)
    try:
        strips = read_almen_strips(path)
        result = almen_strips_intensity(strips, path.name)
    except AlmenStripsError as exc:
        raise UserError(str(exc)) from None
    unit, factor = strips.shown_as

    def show(x: float) -> str:
        return f"{x * factor:.4g} {unit}"

    t = result.saturation_exposure
    print(f"{path.name}: {result.n_strips} strips at {result.n_exposures} exposures ({strips.exposure_column}), "
          f"{types[strip]}")
    print(f"intensity   {_mm(result.intensity_m)} = {shop_notation(result.intensity_m, strip)}   "
          f"({result.model} fit{'' if result.qualified else ', NOT QUALIFIED'})")
    print(f"saturation  T = {show(t)}: doubling the exposure to 2T = {show(2 * t)} raises the arc height by 10 %")
    print("fits (residual: RMS misfit / residual standard error sqrt(SSR/(n-k)), um):")
    for v in result.verdicts:
        mark = "  <- reported" if v.model == result.model else ""
        curve = MODELS[v.model][1]
        if not v.ok:
            print(f"  {v.model:4s}  {curve:22s}  failed: {v.error}{mark}")
            continue
        verdict = "qualified" if v.qualified else "; ".join(v.problems(strips.shown_as))
        print(f"  {v.model:4s}  {curve:22s}  {_mm(v.fit.intensity)} = {shop_notation(v.fit.intensity, strip):6s}  "
              f"T = {show(v.fit.saturation_shots):14s}  residual {v.residual_rms_m * 1e6:.3g} / "
              f"{v.residual_se_m * 1e6:.3g}  {verdict}{mark}")
    print(f"reported: {result.reason}")
    return 0 if result.qualified else 1

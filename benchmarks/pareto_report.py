"""The Pareto study's report: the markdown file (tables, headline ratios, machine) and the PNG figure.

The method: the docstring of ``benchmarks/pareto.py``.
"""

from __future__ import annotations

import datetime
import math
import statistics
from pathlib import Path

import common
from pareto_analysis import (
    envelope,
    equal_accuracy_lines,
    equal_accuracy_ratios,
    fit_costs,
    pareto_front,
    rank_agreement,
)
from pareto_cases import NOT_STEADY_2D, TOLERANCES, AutoChoice, Row, fmt_error, fmt_time
from pareto_measure import PAIRED_ROUNDS

ERROR_FLOOR = 1e-16  # plotted instead of an exact 0
LOWEST_COST_SLACK = 1.5  # auto's time within this factor of the cheapest measured setting counts as the lowest cost


def plot(rows: list[Row], choices: list[AutoChoice], path: Path) -> None:
    """Write the figure: error vs time of every setting per family, each case's Pareto front, auto's choices."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    families = list(dict.fromkeys(r.family for r in rows))
    fig, axes = plt.subplots(2, 4, figsize=(22, 10.5))
    colours = {"closed_form": "black", "polynomial": "tab:blue", "discretised": "tab:orange",
               "quasi-static": "tab:gray", "relaxation": "tab:green", "transient": "tab:orange",
               "transient pair": "tab:brown", "3D linear": "tab:gray", "3D fastsim": "tab:green",
               "3D strips": "tab:blue", "3D discretised": "tab:orange"}
    markers = "osD^vP*X"
    for ax, family in zip(axes.flat, families, strict=False):
        cases = list(dict.fromkeys(r.case for r in rows if r.family == family))
        for ci, case in enumerate(cases):
            case_rows = [r for r in rows if r.family == family and r.case == case and math.isfinite(r.error)]
            groups = {}
            for r in case_rows:
                groups.setdefault((r.method, tuple(r.options)), []).append(r)
            for (method, keys), group in groups.items():
                hollow = "order" in keys
                ax.plot([r.time for r in group], [max(r.error, ERROR_FLOOR) for r in group],
                        marker=markers[ci % len(markers)], ls=":" if hollow else "-", lw=0.8,
                        color=colours.get(method, "tab:purple"), mfc="none" if hollow else colours.get(method),
                        alpha=0.8, ms=5)
            front = pareto_front(case_rows)
            ax.step([r.time for r in front], [max(r.error, ERROR_FLOOR) for r in front], where="post", color="0.6",
                    lw=2.5, alpha=0.35, zorder=0)
            for choice in (c for c in choices if c.family == family and c.case == case):
                ax.plot(choice.time, max(choice.error, ERROR_FLOOR), marker="*", color="red", ms=13, mec="darkred",
                        zorder=5)
                ax.annotate(f"{choice.tolerance:.0e}", (choice.time, max(choice.error, ERROR_FLOOR)), fontsize=7,
                            color="darkred", xytext=(4, 2 + 7 * (TOLERANCES.index(choice.tolerance)
                                                            if choice.tolerance in TOLERANCES else 0)),
                            textcoords="offset points")
        for tolerance in TOLERANCES:
            ax.axhline(tolerance, color="red", lw=0.5, ls="--", alpha=0.4)
        ax.set_xscale("log")
        ax.set_yscale("log")
        ax.set_title(f"{family} ({len(cases)} case{'s' if len(cases) > 1 else ''})", fontsize=10)
        ax.set_xlabel("time per step [s]" if family == "instationary" else "time per solve [s]")
        ax.set_ylabel({"instationary": "max |T' - T'_ref| / (mu N')",
                       "elliptic (3D)": "max error of Fx, Fy / (mu Fn), Mz / (mu Fn c)"}.get(
                           family, "relative error of T' and p0"))
        ax.grid(True, which="major", alpha=0.3)
        legend = [plt.Line2D([], [], color=colours.get(m, "tab:purple"), marker="o", ls="-", label=m.replace("_", " "))
                  for m in dict.fromkeys(r.method for r in rows if r.family == family)]
        legend += [plt.Line2D([], [], color="k", marker=markers[i % len(markers)], ls="none", mfc="none",
                              label=c[:38]) for i, c in enumerate(cases)]
        legend += [plt.Line2D([], [], color="red", marker="*", ls="none", ms=11, label="auto at tolerance"),
                   plt.Line2D([], [], color="0.6", lw=2.5, alpha=0.4, label="Pareto front (per case)")]
        ax.legend(handles=legend, fontsize=6.5, loc="best")
    for ax in list(axes.flat)[len(families):]:
        ax.axis("off")
    fig.suptitle("rollcontact: error vs time per setting (log-log); dotted/hollow: explicit polynomial orders",
                 fontsize=12)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def fmu_overhead_lines(rows: list[Row], empty: float) -> list[str]:
    """Headline lines: each steady setting's FMU step over its solve() and the difference, per method (the FMU's
    own share: pythonfmu's step, the model building the scene and its outputs, fmpy's calls)."""
    lines = []
    for method in ("closed_form", "polynomial", "discretised"):
        pairs = [(r.fmu_time, r.time) for r in rows if r.method == method and r.family not in NOT_STEADY_2D
                 and math.isfinite(r.fmu_time) and math.isfinite(r.time)]
        if not pairs:
            continue
        ratios = [f / t for f, t in pairs]
        extra = statistics.median(f - t for f, t in pairs)
        lines.append(f"- FMU step over solve() of the same setting, {method.replace('_', ' ')}: median "
                     f"{statistics.median(ratios):.3g}x (range {min(ratios):.3g}-{max(ratios):.3g}x over {len(pairs)} "
                     f"settings); the FMU adds a median {fmt_time(extra)} per step"
                     + (f" (the empty FMU step: {fmt_time(empty)})" if math.isfinite(empty) else ""))
    return lines


TENS_OF_US = 100e-6  # s: "tens of microseconds"
CONTACT_CARTER = 2e-3  # s: CONTACT on a 100-element 2D Carter case, as the brief quotes it for these machines
CONTACT_FALLING = (7e-3, 20e-3)  # s: CONTACT on a falling-friction case, likewise


def auto_times(choices: list[AutoChoice], rows: list[Row], family: str, tolerance: float = 1e-3) -> list[float]:
    """auto's times per solve at ``tolerance`` on the family's one-patch cases (no setting found more patches)
    where it met it."""
    one_patch = ({r.case for r in rows if r.family == family}
                 - {r.case for r in rows if r.family == family and r.patches > 1})
    return [c.time for c in choices if c.family == family and c.case in one_patch and c.tolerance == tolerance
            and c.error <= tolerance and math.isfinite(c.time)]


def aims_lines(rows: list[Row], choices: list[AutoChoice], fmu: list) -> list[str]:
    """The brief's aims against this run's figures: a table of aim, measurement and verdict."""

    def span(values: list[float]) -> str:
        return (f"median {fmt_time(statistics.median(values))}, max {fmt_time(max(values))} over {len(values)} "
                "case(s)")

    out = []
    closed = [ratio for label, _, ratio, _, _ in fmu if label.startswith("closed form")]
    if closed:
        out.append(("closed-form FMU step within 1.5x an empty pythonfmu step", f"{closed[0]:.2f}x",
                    closed[0] <= 1.5))
    tables = [(label.split(",")[0], ratio) for label, _, ratio, _, _ in fmu if "certified table" in label]
    if tables:
        out.append(("FMU steps of falling friction and corrugation within 3x an empty pythonfmu step (the certified "
                    "table, 1e-3 mu N)", ", ".join(f"{family} {ratio:.2f}x" for family, ratio in tables),
                    max(ratio for _, ratio in tables) <= 3.0))
    for family, what in (("corrugation", "corrugated"), ("velocity-dependent friction", "falling-friction")):
        values = auto_times(choices, rows, family)
        if values:
            out.append((f"{what} solves in tens of microseconds at 0.1 % (`solve(scene, tolerance=1e-3)`, one "
                        "patch)", span(values), max(values) < TENS_OF_US))
    ratios = equal_accuracy_ratios([r for r in rows if r.family not in NOT_STEADY_2D], 1e-3, False)
    if ratios:
        median = statistics.median(q.ratio for q in ratios)
        bounds = sum(q.lower_bound for q in ratios)
        out.append(("the polynomial method 1000x faster than the discretised solver at equal accuracy (1e-3)",
                    f"median {median:.3g}x over {len(ratios)} cases ({bounds} lower bounds)", median >= 1000.0))
    for family, contact, figure in (("Hertz/Carter", f"~{fmt_time(CONTACT_CARTER)} on a 100-element Carter case",
                                     CONTACT_CARTER),
                                    ("velocity-dependent friction", f"{fmt_time(CONTACT_FALLING[0])}-"
                                     f"{fmt_time(CONTACT_FALLING[1])} on a falling-friction case",
                                     CONTACT_FALLING[0])):
        chosen = auto_times(choices, rows, family, 1e-2)
        like = [r for r in rows if r.family == family and r.patches == 1 and r.method == "discretised"
                and r.options == {"elements": 100} and math.isfinite(r.time)]
        if chosen:
            measured = (f"auto at 1e-2 (CONTACT's ~1 % errors): {span(chosen)}, {figure / max(chosen):.3g}x faster at "
                        "worst")
            if like:
                measured += (f"; like for like, discretised n = 100: {span([r.time for r in like])}, error up to "
                             f"{fmt_error(max(r.error for r in like))}")
            out.append((f"faster than CONTACT's {contact} at ~1 % (quoted, not run here)", measured,
                        max(chosen) < figure))
    if not out:
        return []
    return ["## Against the brief's aims", "",
            "The aims of the project brief, each against this run's figures (CONTACT's times are the brief's, for "
            "these machines; CONTACT itself is not run).  Zero crashes over the input domain is the property "
            "tests' (`tests/test_properties.py`, `tests/test_fmu_properties.py`), not this study's.", "",
            "| aim | this run | met |", "|---|---|---|",
            *(f"| {aim} | {measured} | {'yes' if met else '**no**'} |" for aim, measured, met in out), ""]


def auto_summary(choices: list[AutoChoice]) -> list[str]:
    """Headline lines: how often auto met t, and its cost over the cheapest measured setting that met t."""
    met = [c for c in choices if c.error <= c.tolerance]
    reachable = [c for c in choices if not math.isnan(c.cheapest_time)]
    ratios = [c.paired for c in reachable if c.error <= c.tolerance]
    lines = [f"- auto met the requested tolerance in {len(met)} of {len(choices)} cases (t = "
             f"{', '.join(f'{t:.0e}' for t in TOLERANCES)}); some setting measured met it in {len(reachable)}"]
    certified = [c.certified_paired for c in choices if not math.isnan(c.certified_paired)]
    for what, values in (("the cheapest measured setting meeting t, where auto met t", ratios),
                         ("the cheapest measured setting whose a-priori error bound meets t (what can be known "
                          "before solving)", certified)):
        if values:
            lines.append(f"- auto's time over {what} (timed alternately, {PAIRED_ROUNDS} rounds): median "
                         f"{statistics.median(values):.2f}x, max {max(values):.2f}x; within {LOWEST_COST_SLACK}x "
                         f"(timing noise and the choice itself) in {sum(r <= LOWEST_COST_SLACK for r in values)} of "
                         f"{len(values)}")
    return lines


def report(config, rows, choices, references, inst_refs, fmu, elapsed, load, path: Path) -> None:
    """Write the markdown report of a run to ``path``: machine, headline ratios, aims, references, auto's choices,
    every setting, the cost and error models, the FMU steps."""
    lines = ["# Speed-accuracy Pareto study" + (" (quick smoke test)" if config.quick else ""), "",
             f"Generated {datetime.datetime.now().isoformat(timespec='seconds')} by "
             f"`.venv/bin/python benchmarks/pareto.py{' --quick' if config.quick else ''}` in {elapsed:.0f} s "
             "(figure: `pareto.png`).  Method and definitions: the docstring of `benchmarks/pareto.py`.", "",
             "## Machine", "", *common.machine(load), "",
             "Timings on this shared machine are noisy (other jobs run alongside): ratios measured in the same run "
             "are meaningful, absolute times only roughly.", ""]
    # headline ratios
    lines += ["## Headline ratios (same run)", ""]
    closed = statistics.median([r.time for r in rows if r.method == "closed_form"])
    ratio_lines, ratio_table = equal_accuracy_lines(rows)
    lines += ratio_lines
    if fmu:
        for label, _, ratio, _, _ in fmu[1:]:
            lines.append(f"- FMU step / empty pythonfmu FMU step, {label}: {ratio:.3g}x")
    lines += fmu_overhead_lines(rows, fmu[0][1] * 1e-6 if fmu else math.nan)
    lines += auto_summary(choices)
    lines.append(f"- Each method vs the closed form (solve() on Hertz/Carter, {fmt_time(closed)}):")
    for title, selector in (
            ("polynomial, corrugation (the setting auto chose at 1e-3, run directly)",
             lambda r: r.family == "corrugation" and r.method == "polynomial" and 1e-3 in r.auto),
            ("polynomial, velocity-dependent friction, one patch (the setting auto chose at 1e-3, run directly)",
             lambda r: r.family.startswith("velocity") and r.method == "polynomial" and 1e-3 in r.auto
             and r.patches == 1),
            ("polynomial, velocity-dependent friction, split contact (the setting auto chose at 1e-3, run directly)",
             lambda r: r.family.startswith("velocity") and r.method == "polynomial" and 1e-3 in r.auto
             and r.patches > 1),
            ("discretised n = 200, Coulomb", lambda r: r.method == "discretised" and r.options == {"elements": 200}
             and r.family != "velocity-dependent friction"),
            ("discretised n = 200, velocity-dependent, one patch", lambda r: r.method == "discretised"
             and r.options == {"elements": 200} and r.family == "velocity-dependent friction" and r.patches == 1),
            ("discretised n = 200, velocity-dependent, split contact", lambda r: r.method == "discretised"
             and r.options == {"elements": 200} and r.family == "velocity-dependent friction" and r.patches > 1),
            ("quasi-static step", lambda r: r.method == "quasi-static"),
            ("relaxation step", lambda r: r.method == "relaxation"),
            ("transient step, n = 100", lambda r: r.method == "transient" and r.options == {"elements": 100})):
        times = [r.time for r in rows if selector(r)]
        if times:
            median = statistics.median(times)
            lines.append(f"  - {title}: {median / closed:.3g}x (median {fmt_time(median)} over {len(times)} "
                         "case(s))")
    lines += ratio_table
    lines += aims_lines(rows, choices, fmu)
    # references
    lines += ["## References", "", "| family | case | reference | cross-check |", "|---|---|---|---|"]
    for (family, case), ref in references.items():
        lines.append(f"| {family} | {case} | {ref.how} | {ref.check or '-'} |")
    for case, how, check in inst_refs:
        lines.append(f"| instationary | {case} | {how} | {check} |")
    lines.append("")
    # auto
    lines += ["## auto at each requested tolerance", "",
              "auto takes the cheapest setting (by the cost models of `methods/*/accuracy.py`) whose predicted "
              "error bound meets t.  "
              "Steady: `solve(scene, tolerance=t)`; instationary: the FMU's stepping model with `transient = 1` "
              "(auto) and `tolerance = t` (it switches between quasi-static Carter, the relaxation lag while the "
              "lag's bound for the creep swing seen over the last 8 relaxation lengths meets t, and the discretised "
              "transient, a pair of nested grids extrapolated, where it does not; the lag's 'bound' below is the "
              "largest over the measured cycle).  "
              "'cheapest measured' is the fastest measured setting whose error is <= t (by measured time, so "
              "noise and lucky cancellations count).  'x cheapest': auto's time over it, timed again alternately "
              f"with it ({PAIRED_ROUNDS} rounds, the median ratio: the machine's speed drifts over the minutes "
              "between the rows); 'unpaired': the ratio of the times in the table, with the time of auto's setting "
              "run directly over it in brackets (steady: the rest is the choice itself; instationary: where every "
              "measured step ran one model, the rest is the model's overhead).  'cheapest certified': the fastest "
              "measured setting whose a-priori error bound (the 'bound' column below) meets t, the best choice "
              "possible without hindsight of the errors; 'x certified': auto's time over it, timed alternately "
              "likewise.  'FMU step': the contact FMU with `method = 0` (auto) and `tolerance = t` stepped through "
              "fmpy on the same scene (steady cases; the instationary times are already steps of the FMU's model).",
              "",
              "| family | case | t | auto's choice | error | estimate | meets t | time | FMU step | cheapest measured "
              "meeting t | x cheapest | unpaired | cheapest certified | x certified |",
              "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"]
    for c in choices:
        meets = "yes" if c.error <= c.tolerance else "**no**"
        ratio = "-" if math.isnan(c.cheapest_time) else f"{c.time / c.cheapest_time:.2f}" + (
            "" if math.isnan(c.chosen_time) else f" ({c.chosen_time / c.cheapest_time:.2f})")
        paired = "-" if math.isnan(c.paired) else f"{c.paired:.2f}"
        lines.append(f"| {c.family} | {c.case} | {c.tolerance:.0e} | {c.label} | {fmt_error(c.error)} | "
                     f"{fmt_error(c.estimate)} | {meets} | {fmt_time(c.time)} | {fmt_time(c.fmu_time)} | "
                     f"{c.cheapest or 'none'} | {paired} | "
                     f"{ratio} | {c.certified or 'none'} | "
                     f"{'-' if math.isnan(c.certified_paired) else f'{c.certified_paired:.2f}'} |")
    lines.append("")
    # per family tables
    lines += ["## Every setting", "",
              "error: the larger of the T' and p0 errors (instationary: T' in units of mu N').  time: per solve() "
              "(instationary: per step of the FMU's model).  FMU step: the contact FMU running the same setting on "
              "the same scene, per fmpy step (set 3 inputs, doStep, get 11 outputs; `common.steady_step_time`): "
              "'-' where no FMU parameter selects the setting (the slip iteration's nodes, the extrapolated "
              "discretised pairs) and for the instationary rows, whose times are already model steps.  model: the "
              "cost model of `methods/*/accuracy.py` [s] and the predicted error bound; 'front': on the case's Pareto "
              "front; "
              "'auto': the tolerances at which auto chose this setting.", ""]
    for family in dict.fromkeys(r.family for r in rows):
        lines += [f"### {family}", "",
                  "| case | setting | error T' | error p0 | error | time | FMU step | model cost | bound | front "
                  "| auto |",
                  "|---|---|---|---|---|---|---|---|---|---|---|"]
        for case in dict.fromkeys(r.case for r in rows if r.family == family):
            case_rows = [r for r in rows if r.family == family and r.case == case]
            front = {id(r) for r in pareto_front(case_rows)}
            for r in case_rows:
                lines.append(f"| {case} | {r.label}{' (' + r.note + ')' if r.note else ''} | "
                             f"{fmt_error(r.error_force)} | {fmt_error(r.error_pressure)} | {fmt_error(r.error)} | "
                             f"{fmt_time(r.time)} | {fmt_time(r.fmu_time)} | {fmt_time(r.model_cost)} | "
                             f"{fmt_error(r.bound)} | "
                             f"{'x' if id(r) in front else ''} | {', '.join(f'{t:.0e}' for t in r.auto)} |")
        lines.append("")
    # model checks
    steady = [r for r in rows if r.family not in NOT_STEADY_2D]
    rho, agree, pairs = rank_agreement(steady)
    lines += ["## Cost and error models of auto (`src/rollcontact/methods/*/accuracy.py`) against this run", "",
              f"- Cost model vs measured time: Spearman rank correlation {rho:.3f} over {len(steady)} settings; "
              f"same-case pairs whose times differ by > 30 % ordered alike: {agree:.0%} of {pairs}.",
              "- Fitted constants (least squares on relative residuals; update the accuracy modules when the ranking "
              "drifts):",
              "", "| constant | in the package | fitted here |", "|---|---|---|"]
    lines += [f"| {name} | {now} | {fitted} |" for name, now, fitted in fit_costs(steady)]
    violations = [r for r in rows if math.isfinite(r.bound) and math.isfinite(r.error) and r.error > r.bound]
    ratios = [r.bound / max(envelope(steady, r), 1e-15) for r in steady
              if math.isfinite(r.bound) and math.isfinite(r.error) and r.method != "closed_form"
              and "tolerance" not in r.options]
    lines += ["", f"- Error bounds violated (error > bound, every family): {len(violations)}"
              + "".join(f"; {r.case}, {r.label}: {r.error:.2e} > {r.bound:.2e}" for r in violations),
              f"- How pessimistic (bound over the converged error, discretised and slip-node settings): median "
              f"{statistics.median(ratios):.3g}, max {max(ratios):.3g}" if ratios else "", ""]
    if fmu:
        lines += ["## FMU step (fmpy, one step = setReal(3) + doStep + getReal(10) + getInteger(1))", "",
                  "| case | median us/step | x empty FMU | discarded | method_used |", "|---|---|---|---|---|"]
        lines += [f"| {label} | {us:.1f} | {ratio:.2f} | {discards} | {sorted(used)} |"
                  for label, us, ratio, discards, used in fmu]
        lines.append("")
    path.write_text("\n".join(lines))

"""The campaign as tasks: one per flight and step, with explicit dependencies.

    plan = build_plan(campaign, digests)
    plan.tasks                     # topological order: exports, calibrations, estimates, maps,
                                   # reports, merges
    plan.by_subject["b15_03"]      # {"export": key, "estimate": key, "map": key, ...}

    export[f]     recording -> flight table                  (recordings only)
    calibrate[h]  still-air flight of helicopter h -> model  (after its export)
    still_air_net[h]  h's still-air flights -> still-air wind net (after their exports)
    estimate[f]   flight + h's model (+ h's net: anchored) -> wind table
                                                  (after calibrate[h], still_air_net[h], export[f])
    map[f]        wind + flight -> the flight's map and its cells on the campaign grid
    report[f]     flight + model + wind -> model report      (after estimate[f])
    merge[beta]   every map at that beta -> the merged map

A task's key is its content address (`store.task_key`): the step, the digests of its
input files, the keys of the tasks it reads, the model spec, its options and the code
version. `args` carries what the step needs to run (paths, options), `deps` the upstream
keys by role.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from pathlib import Path

from airwake.campaign.spec import ANCHORED, Campaign
from airwake.campaign.store import DigestCache, code_version, task_key


@dataclass(frozen=True)
class Task:
    key: str
    step: str
    subject: str  # flight name, helicopter name, or "beta <b>"
    deps: dict = field(default_factory=dict)  # role -> upstream key
    args: dict = field(default_factory=dict)


@dataclass
class Plan:
    tasks: list
    by_subject: dict  # subject -> {step: key}
    code: str

    def task(self, key: str) -> Task:
        return self._index[key]

    def __post_init__(self) -> None:
        self._index = {t.key: t for t in self.tasks}


def beta_subject(beta: float) -> str:
    return f"beta {beta:g}"


def _model_identity(spec: str, digests: DigestCache) -> dict:
    """A shipped spec by name and bytes, a spec file by its bytes."""
    from airwake.heli.spec import builtin_spec

    path = Path(spec) if Path(spec).is_absolute() else builtin_spec(spec)
    return {"spec": Path(spec).name, "digest": digests.digest(path)}


def build_plan(campaign: Campaign, digests: DigestCache) -> Plan:
    """Every task of the campaign (module docstring), keys computed from the inputs."""
    code = code_version()
    steps = set(campaign.steps)
    opts = campaign.options
    tasks: list[Task] = []
    subjects: dict[str, dict] = {}
    seen: set[str] = set()

    def add(step, subject, identity, deps, args) -> str:
        key = task_key(step, {"step": step, "code": code, "options": opts.get(step, {}),
                              **identity, "deps": deps})
        if key not in seen:  # two identical inputs share one result
            seen.add(key)
            tasks.append(Task(key, step, subject, dict(deps), args))
        subjects.setdefault(subject, {})[step] = key
        return key

    def flight_input(name, source):
        """(identity, deps, args) of a flight's table: the file, or its export."""
        if source.kind == "recording":
            key = add("export", name, {"recording": digests.digest(source.path)}, {},
                      {"recording": str(source.path), "options": opts["export"]})
            return {}, {"flight": key}, {}
        return {"flight": digests.digest(source.path)}, {}, {"flight": str(source.path)}

    models = {}
    for h in campaign.helicopters.values():
        start = _model_identity(h.model, digests)
        if h.calibration is not None and "calibrate" in steps:
            ident, deps, args = flight_input(f"calibration {h.name}", h.calibration)
            models[h.name] = ({}, {"model": add(
                "calibrate", h.name, {**ident, "start": start}, deps,
                {**args, "start": h.model, "helicopter": h.name,
                 "options": opts["calibrate"]})}, {})
        else:
            models[h.name] = ({"model": start}, {}, {"model": h.model})

    nets = {}  # helicopter -> the key of its still-air net
    flying = {f.helicopter for f in campaign.flights}
    for h in campaign.helicopters.values():
        # a net only where an estimate reads it
        if ("estimate" not in steps or h.name not in flying
                or campaign.estimate_method(h.name) != ANCHORED):
            continue
        ident, deps, files = {}, {}, []
        for i, source in enumerate(h.still_air_flights):
            role = f"flight {i}"
            f_ident, f_deps, f_args = flight_input(f"still air {h.name} {i}", source)
            ident.update({role: f_ident["flight"]} if f_ident else {})
            deps.update({role: f_deps["flight"]} if f_deps else {})
            files += [(role, f_args["flight"])] if f_args else []
        nets[h.name] = add("still_air_net", h.name, ident, deps,
                           {"flights": dict(files), "helicopter": h.name,
                            "options": opts["still_air_net"]})

    maps_by_beta: dict[float, dict] = {}
    for f in campaign.flights:
        f_ident, f_deps, f_args = flight_input(f.name, f.source)
        m_ident, m_deps, m_args = models[f.helicopter]
        wind = None
        if "estimate" in steps:
            net = ({"net": digests.digest(Path(opts["estimate"]["net"]))}
                   if "net" in opts["estimate"] else {})
            method = campaign.estimate_method(f.helicopter)
            anchor = {"net": nets[f.helicopter]} if method == ANCHORED else {}
            wind = add("estimate", f.name, {**f_ident, **m_ident, **net, "method": method},
                       {**f_deps, **m_deps, **anchor},
                       {**f_args, **m_args, "options": {**opts["estimate"], "method": method}})
        if "map" in steps:
            key = add("map", f.name, {**f_ident, "grid": campaign.grid.__dict__},
                      {**f_deps, "wind": wind},
                      {**f_args, "grid": campaign.grid, "options": opts["map"]})
            maps_by_beta.setdefault(f.beta_deg, {})[f.name] = key
        if "report" in steps:
            w = {"wind": wind} if wind else {}
            add("report", f.name, {**f_ident, **m_ident}, {**f_deps, **m_deps, **w},
                {**f_args, **m_args, "options": opts["report"]})
    for beta, maps in sorted(maps_by_beta.items()):
        add("merge", beta_subject(beta), {"beta_deg": beta, "grid": campaign.grid.__dict__},
            {f"map {name}": key for name, key in sorted(maps.items())},
            {"beta_deg": beta, "grid": campaign.grid})
    return Plan(tasks, subjects, code)

"""``tune`` from several starting points (``modalfe.design.multistart.run_starts``): one start as a picklable task,
and the best of the runs' results."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field

from modalfe.design.tuning import FrequencyTarget, TuningResult, tune
from modalfe.response.sensitivity import with_values


@dataclass(frozen=True)
class TuneTask:
    """``tune`` from one start (a dict of parameter values), as a picklable callable for
    ``modalfe.design.multistart.run_starts``: the scene, the targets, the parameters and ``tune``'s options."""

    scene: object
    targets: tuple[FrequencyTarget, ...]
    parameters: tuple[str, ...]
    options: Mapping = field(default_factory=dict)

    def __call__(self, start: Mapping[str, float]) -> TuningResult:
        return tune(with_values(self.scene, start), self.targets, self.parameters, **self.options)


def best_result(results: Sequence) -> int:
    """Index of the best of several runs' results (exceptions last): converged first, then the highest merit
    (k_eff, the least voltage) when maximizing, then the smallest residual."""
    def key(i: int):
        r = results[i]
        if not isinstance(r, TuningResult):
            return (2, 0.0, 0.0)
        k = r.final.merit if r.maximize else 0.0
        return (0 if r.converged else 1, -k, r.residual)

    return min(range(len(results)), key=key)

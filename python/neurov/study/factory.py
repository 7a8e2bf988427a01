"""A user's controller in a study, named by import path: ``factory =
"my_package.my_module:make_controller"``, a function of the scenario that
returns a controller (:class:`neurov.Controller`), or a batched policy
(:class:`neurov.laws.protocol.BatchedController`, ``batched = True``): that
product is made once per scenario for each worker's batch of runs and steps
all of that batch's runs of the scenario in one call per step
(docs/custom-controllers.md).

The study holds only the path (a string; it pickles to the workers) and each
process imports it: a study file that names a factory runs that code on every
worker, so a study file is to be trusted like a script.
"""

from __future__ import annotations

import importlib
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

from neurov.errors import FactoryError
from neurov.laws.protocol import is_batched
from neurov.config.scenario import Scenario

__all__ = ["ControllerFactory", "FactoryError"]


@dataclass(frozen=True)
class ControllerFactory:
    path: str
    """``"module.path:function"`` (the function may be an attribute path, ``mod:Class.make``)."""
    label: str
    arguments: tuple[tuple[str, Any], ...] = ()
    """Keyword arguments the function is called with after the scenario
    (``[controllers.KEY.arguments]``): what a tuning searches."""

    def load(self) -> Callable[[Scenario], Any]:
        """The function the path names; :class:`FactoryError` saying what is missing."""
        module_name, sep, attr = self.path.partition(":")
        if not sep or not module_name or not attr:
            raise FactoryError(f"factory {self.path!r}: expected 'module.path:function'")
        try:
            obj: Any = importlib.import_module(module_name)
        except Exception as e:  # an import runs the user's module: any error is theirs to see
            raise FactoryError(f"factory {self.path!r}: cannot import module {module_name!r} "
                               f"({type(e).__name__}: {e}); is it on PYTHONPATH of every worker?") from None
        for part in attr.split("."):
            if not hasattr(obj, part):
                raise FactoryError(f"factory {self.path!r}: module {module_name!r} has no {attr!r}")
            obj = getattr(obj, part)
        if not callable(obj):
            raise FactoryError(f"factory {self.path!r}: {attr!r} is a {type(obj).__name__}, not a function")
        return obj  # type: ignore[no-any-return]

    def make(self, scenario: Scenario) -> Any:
        """A fresh controller for `scenario` (the nominal one: a controller is
        designed for the vehicle as documented, not the plant as perturbed)."""
        make = self.load()
        try:
            controller = make(scenario, **dict(self.arguments))
        except Exception as e:
            raise FactoryError(f"factory {self.path!r} raised {type(e).__name__} for scenario "
                               f"{scenario.name!r}: {e}") from e
        if not callable(getattr(controller, "step", None)) and not is_batched(controller):
            raise FactoryError(f"factory {self.path!r} returned a {type(controller).__name__} for scenario "
                               f"{scenario.name!r}, which has no method step(eta, nu, eta_d, eta_d_dot, "
                               f"eta_d_ddot) -> tau (nor batched = True and step_batch)")
        return controller

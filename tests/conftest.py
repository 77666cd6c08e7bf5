"""tests/: hypothesis draws from SEED like the RTL tests (issue 16).

SEED=<n> fixes hypothesis's examples for the whole run (the same effect as pytest's
--hypothesis-seed=<n>; the hypothesis plugin sets the same global, hypothesis.core.global_force_seed).
Without SEED a seed is drawn per process; a failing test's report names it, so
`SEED=<n> pytest ...` repeats the run's examples.
"""
from __future__ import annotations

import os

import pytest
from hypothesis import core, settings


def _session_seed() -> int:
    s = os.environ.get("SEED")
    return int(s) if s else int.from_bytes(os.urandom(4), "little") >> 1


# Hypothesis loads its "ci" profile when the environment says CI (the CI variable is set), and that
# profile derandomizes: every run would draw the same examples and ignore SEED. Keep whatever profile
# is loaded (deadline, database, print_blob) but draw from the seed.
settings.register_profile("seeded", parent=settings.get_profile(settings.get_current_profile_name()),
                          derandomize=False)
settings.load_profile("seeded")

HYPOTHESIS_SEED = _session_seed()
if core.global_force_seed is None:  # --hypothesis-seed on the command line wins
    core.global_force_seed = HYPOTHESIS_SEED


def pytest_report_header(config):
    return f"hypothesis seed (tests/): {core.global_force_seed} (SEED= repeats it)"


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_makereport(item, call):
    outcome = yield
    rep = outcome.get_result()
    if rep.when == "call" and rep.failed:
        rep.sections.append(("hypothesis seed", f"SEED={core.global_force_seed} repeats this run's examples"))

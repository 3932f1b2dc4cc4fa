"""Shared pytest configuration: hypothesis profiles.

The default profile, ``deterministic`` (no environment variable needed), is what CI runs: ``derandomize=True`` derives
each test's examples from the test itself, so the README's test command and CI run exactly the
same examples on every machine and every run, and nothing found on one run can make a later
run fail differently. Per-example deadlines are off (meaningless on a loaded 2-core machine).

``HYPOTHESIS_PROFILE=explore`` is the opt-in random search for new counterexamples: random
seeds (reproducible with ``--hypothesis-seed=N``), more examples, and the example database, so
a failure it finds is replayed until fixed. Every counterexample it finds is then fixed and
pinned with ``@example`` in its test, so the deterministic default covers it forever.
"""

import os

from hypothesis import HealthCheck, settings

settings.register_profile(
    "deterministic",
    deadline=None,
    derandomize=True,
    database=None,
    max_examples=40,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.register_profile(
    "explore",
    deadline=None,
    max_examples=200,
    suppress_health_check=[HealthCheck.too_slow],
)
settings.load_profile(os.environ.get("HYPOTHESIS_PROFILE", "deterministic"))

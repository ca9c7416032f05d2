"""How many examples each hard-case property draws: a few hundred in the default run, 10 000 with
``VC_HARD_CASES=thorough`` (``make test-hard``), where the count per property is the acceptance figure."""

from __future__ import annotations

import os

from hypothesis import HealthCheck, settings

THOROUGH = os.environ.get("VC_HARD_CASES") == "thorough"
EXAMPLES = 10_000 if THOROUGH else 200

#: The settings of every property in tests/hard_cases/.
PROPERTY = settings(max_examples=EXAMPLES, deadline=None, derandomize=not THOROUGH,
                    suppress_health_check=[HealthCheck.too_slow, HealthCheck.data_too_large])

# SPDX-License-Identifier: Apache-2.0
"""How a cocotb driver gets its job: a JSON file named by an environment variable."""
from __future__ import annotations

import json
import os


def job_from_env(name: str):
    """The job in the JSON file named by $<name>_FILE (no size limit), or, from callers not
    yet moved to files, the JSON text in $<name> itself (limited by the system's argument
    and environment size, about 128 KiB)."""
    path = os.environ.get(f"{name}_FILE")
    if path:
        with open(path) as f:
            return json.load(f)
    return json.loads(os.environ[name])

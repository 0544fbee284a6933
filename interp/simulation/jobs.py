# SPDX-License-Identifier: Apache-2.0
"""How a cocotb driver gets its job: a JSON file named by an environment variable."""
from __future__ import annotations

import json
import os
from pathlib import Path


def job_env(name: str, job, folder) -> dict[str, str]:
    """Write `job` as JSON into `folder`; the environment that names it ($<name>_FILE)."""
    path = Path(folder) / f"{name.lower()}.json"
    path.write_text(json.dumps(job))
    return {f"{name}_FILE": str(path)}


def job_from_env(name: str):
    """The job in the JSON file named by $<name>_FILE (no size limit)."""
    with open(os.environ[f"{name}_FILE"]) as f:
        return json.load(f)

from pathlib import Path

import pytest

from cdpr.robot import load_robot

ROOT = Path(__file__).resolve().parents[1]
ROBOTS = ROOT / "config" / "robots"


@pytest.fixture(scope="session")
def cdpr4():
    return load_robot(ROBOTS / "cdpr4.yaml")


@pytest.fixture(scope="session")
def cdpr3():
    return load_robot(ROBOTS / "cdpr3.yaml")

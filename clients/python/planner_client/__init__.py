"""Python client of the planner service (wire v1, docs/wire.md) over iceoryx2."""

from .client import MapInfo, PlannerClient, PlanResult
from .errors import *  # noqa: F401,F403 (the exception hierarchy)
from .errors import STATUS_ERRORS
from .wire import (
    ALGORITHMS, MapHeader, PlanParams, PlanRequest, PlanResponseHeader, Waypoint, pack_rows,
)

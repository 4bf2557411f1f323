"""Wire v1 of the planner service (docs/wire.md): ctypes payloads and codes.

The layouts match clients/c/planner_wire.h (the test checks every size, alignment and
offset against its #defines). `type_name()` is what the iceoryx2 binding declares when it
opens a service; the request header is `()` and the map words are `u32` (the binding's
names for no header and `ctypes.c_uint32`).
"""

import ctypes

WIRE_VERSION = 1
LAYOUT_ROWS = 0
LAYOUT_ROWS_AND_COLUMNS = 1
KIND_PLAN = 0
KIND_MAP_STATUS = 1
MAX_COUNT = 1 << 24  # largest population, iterations, stagnation
MAX_RADIUS_CELLS = 1024
MAX_WAYPOINTS = 16384
MAP_INITIAL_SLICE_LEN = 2 * 512 * 512 // 32  # words a map publisher starts with

ALGORITHMS = {
    "astar": 1, "theta": 2, "aco": 3, "tclhho": 4, "igwo": 5, "hho": 6, "gwo": 7,
    "tgwo": 8, "pso": 9, "ga": 10, "ssa": 11, "ssagwo": 12, "anyangle": 13,
}
GUIDES = {"anyangle": 0, "astar": 1}


class MapHeader(ctypes.Structure):
    """User header of a map frame on `P/map` (32 bytes, align 4)."""

    _fields_ = [
        ("wire_version", ctypes.c_uint16),
        ("layout", ctypes.c_uint8),
        ("reserved", ctypes.c_uint8),
        ("map_id", ctypes.c_uint32),
        ("map_version", ctypes.c_uint32),
        ("width", ctypes.c_uint32),
        ("height", ctypes.c_uint32),
        ("resolution", ctypes.c_float),
        ("origin", ctypes.c_float * 2),
    ]

    @staticmethod
    def type_name() -> str:
        return "planner.v1.MapHeader"


class PlanParams(ctypes.Structure):
    """Planner parameters inside a PlanRequest (32 bytes, align 4); 0 = default."""

    _fields_ = [
        ("radius", ctypes.c_float),
        ("population", ctypes.c_uint32),
        ("iterations", ctypes.c_uint32),
        ("stagnation", ctypes.c_uint32),
        ("clearance", ctypes.c_float),
        ("clearance_weight", ctypes.c_float),
        ("turn_weight", ctypes.c_float),
        ("guide", ctypes.c_uint8),
        ("reserved", ctypes.c_uint8 * 3),
    ]

    @staticmethod
    def type_name() -> str:
        return "planner.v1.PlanParams"


class PlanRequest(ctypes.Structure):
    """Request payload of `P/plan` (104 bytes, align 8)."""

    _fields_ = [
        ("wire_version", ctypes.c_uint16),
        ("kind", ctypes.c_uint8),
        ("algorithm", ctypes.c_uint8),
        ("reserved", ctypes.c_uint32),
        ("request_id", ctypes.c_uint64),
        ("seed", ctypes.c_uint64),
        ("deadline_us", ctypes.c_uint64),
        ("wake_token", ctypes.c_uint64),
        ("polls_until_ns", ctypes.c_uint64),
        ("map_id", ctypes.c_uint32),
        ("map_version", ctypes.c_uint32),
        ("start", ctypes.c_int32 * 2),
        ("goal", ctypes.c_int32 * 2),
        ("params", PlanParams),
    ]

    @staticmethod
    def type_name() -> str:
        return "planner.v1.PlanRequest"


class PlanResponseHeader(ctypes.Structure):
    """Response user header of `P/plan` (72 bytes, align 8)."""

    _fields_ = [
        ("wire_version", ctypes.c_uint16),
        ("status", ctypes.c_uint16),
        ("algorithm", ctypes.c_uint8),
        ("kind", ctypes.c_uint8),
        ("reserved", ctypes.c_uint8 * 2),
        ("request_id", ctypes.c_uint64),
        ("map_id", ctypes.c_uint32),
        ("map_version", ctypes.c_uint32),
        ("held_version", ctypes.c_uint32),
        ("map_width", ctypes.c_uint32),
        ("map_height", ctypes.c_uint32),
        ("waypoints", ctypes.c_uint32),
        ("length", ctypes.c_float),
        ("turns", ctypes.c_uint32),
        ("evaluations", ctypes.c_uint32),
        ("time_us", ctypes.c_float),
        ("map_decode_us", ctypes.c_float),
        ("reserved_end", ctypes.c_uint32),
        ("max_cells", ctypes.c_uint64),
    ]

    @staticmethod
    def type_name() -> str:
        return "planner.v1.PlanResponseHeader"


class Waypoint(ctypes.Structure):
    """Element of the response slice (8 bytes, align 4), in cells."""

    _fields_ = [("x", ctypes.c_float), ("y", ctypes.c_float)]

    @staticmethod
    def type_name() -> str:
        return "planner.v1.Waypoint"


def pack_rows(rows):
    """Packs a grid (a sequence of equally long rows; a truthy cell is blocked) into the
    row-major bits of layout 0: cell (x, y) at bit i % 32 of word i // 32, i = y * width + x.
    Returns (width, height, words)."""
    height = len(rows)
    width = len(rows[0]) if height else 0
    if width == 0:
        raise ValueError("a map needs at least one cell")
    words = [0] * ((width * height + 31) // 32)
    i = 0
    for y, row in enumerate(rows):
        if len(row) != width:
            raise ValueError(f"row {y} has {len(row)} cells, row 0 has {width}")
        for cell in row:
            if cell:
                words[i >> 5] |= 1 << (i & 31)
            i += 1
    return width, height, words

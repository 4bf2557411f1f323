"""Tests of the Python client against a real planner-server (unittest, no other install).

    PLANNER_SERVER=target/release/planner-server python clients/python/test_client.py

Starts the server with a unique --prefix and stops it (SIGTERM) at the end, also on failure.
"""

import ctypes
import math
import os
import queue
import re
import signal
import subprocess
import sys
import threading
import time
import unittest
from pathlib import Path

import iceoryx2 as iox2

HERE = Path(__file__).resolve().parent
ROOT = HERE.parents[1]
sys.path.insert(0, str(HERE))
import planner_client as pc  # noqa: E402
from planner_client import wire  # noqa: E402

SERVER = Path(os.environ.get("PLANNER_SERVER", ROOT / "target" / "release" / "planner-server"))
if not SERVER.is_absolute():
    SERVER = ROOT / SERVER
PREFIX = f"pyclient-test-{os.getpid()}"
SERVERS = []


def start_server(prefix):
    """A planner-server on `prefix`, once it says it is ready (its log is its stderr)."""
    proc = subprocess.Popen([str(SERVER), "--prefix", prefix], stderr=subprocess.PIPE,
                            text=True, env={**os.environ, "RUST_LOG": "info"})
    SERVERS.append(proc)
    lines = queue.Queue()  # read to the end, so that a chatty server never blocks on a pipe
    threading.Thread(target=lambda: [*map(lines.put, proc.stderr), lines.put(None)],
                     daemon=True).start()
    log = []
    deadline = time.monotonic() + 10
    while (left := deadline - time.monotonic()) > 0:
        try:
            line = lines.get(timeout=left)
        except queue.Empty:
            break
        if line is None:  # it exited
            break
        log.append(line)
        if "planner-server ready" in line:
            return proc
    raise AssertionError(f"planner-server on {prefix} did not start:\n{''.join(log)}")


def stop_server(proc):
    if proc.poll() is None:
        proc.send_signal(signal.SIGTERM)
        try:
            proc.wait(timeout=10)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def setUpModule():
    unittest.addModuleCleanup(lambda: [stop_server(p) for p in SERVERS])
    start_server(PREFIX)


def existing_services(prefix):
    """Which of the server's services exist under `prefix`."""
    pattern = iox2.MessagingPattern
    wanted = {"map": pattern.PublishSubscribe, "plan": pattern.RequestResponse,
              "plan-wake": pattern.Event}
    return [name for name, kind in wanted.items() if iox2.Service.does_exist(
        iox2.ServiceName.new(f"{prefix}/{name}"), iox2.config.global_config(), kind,
        iox2.ServiceType.Ipc)]


def warehouse(width=37, height=23):
    """Shelves two cells deep; the width is no multiple of 32 (rows straddle words)."""
    rows = [[0] * width for _ in range(height)]
    for y in range(2, height - 2):
        for x in range(3, width - 3):
            rows[y][x] = int(y % 5 in (2, 3) and x % 12 != 0)
    return rows


def parse_header(path=ROOT / "clients" / "c" / "planner_wire.h"):
    """The header's numeric #defines {NAME: int}, string #defines, and code comments."""
    text = path.read_text()
    numbers = {m[1]: int(m[2]) for m in re.finditer(r"#define (PLANNER_\w+) (\d+)u", text)}
    strings = dict(re.findall(r'#define (PLANNER_TYPE_NAME_\w+) "([^"]+)"', text))
    named = {m[1]: (int(m[2]), m[3]) for m in
             re.finditer(r"#define (PLANNER_(?:STATUS|ALGORITHM)_\w+) (\d+)u /\* (\S+) \*/", text)}
    return numbers, strings, named


class Layout(unittest.TestCase):
    """Python, C and Rust agree: every size, alignment, offset, type name and code."""

    STRUCTS = {"MAP_HEADER": wire.MapHeader, "PLAN_PARAMS": wire.PlanParams,
               "PLAN_REQUEST": wire.PlanRequest,
               "PLAN_RESPONSE_HEADER": wire.PlanResponseHeader, "WAYPOINT": wire.Waypoint}

    def test_structures_match_the_c_header(self):
        numbers, strings, _ = parse_header()
        for name, cls in self.STRUCTS.items():
            key = f"PLANNER_V1_{name}_"
            self.assertEqual(ctypes.sizeof(cls), numbers[key + "SIZE"], name)
            self.assertEqual(ctypes.alignment(cls), numbers[key + "ALIGN"], name)
            offsets = {k[len(key) + 7:].lower(): v for k, v in numbers.items()
                       if k.startswith(key + "OFFSET_")}
            ours = {f: getattr(cls, f).offset for f, _ in cls._fields_}
            self.assertEqual(ours, offsets, name)
            type_name = strings.get(f"PLANNER_TYPE_NAME_{name}", f"planner.v1.{cls.__name__}")
            self.assertEqual(cls.type_name(), type_name)
        # What the binding declares for the map words.
        self.assertEqual(iox2.get_type_name(ctypes.c_uint32), "u32")

    def test_codes_and_limits_match_the_c_header(self):
        numbers, _, named = parse_header()
        statuses = {code: n for k, (code, n) in named.items() if "_STATUS_" in k and code}
        self.assertEqual({c: cls.__name__ for c, cls in pc.STATUS_ERRORS.items()}, statuses)
        algorithms = {n: code for k, (code, n) in named.items() if "_ALGORITHM_" in k}
        self.assertEqual(wire.ALGORITHMS, algorithms)
        for ours, theirs in [(wire.WIRE_VERSION, "WIRE_VERSION"), (wire.MAX_COUNT, "MAX_COUNT"),
                             (wire.MAX_WAYPOINTS, "MAX_WAYPOINTS"),
                             (wire.MAX_RADIUS_CELLS, "MAX_RADIUS_CELLS"),
                             (wire.LAYOUT_ROWS, "LAYOUT_ROWS"), (wire.KIND_PLAN, "KIND_PLAN"),
                             (wire.KIND_MAP_STATUS, "KIND_MAP_STATUS"),
                             (wire.GUIDES["anyangle"], "GUIDE_ANYANGLE"),
                             (wire.GUIDES["astar"], "GUIDE_ASTAR")]:
            self.assertEqual(ours, numbers["PLANNER_" + theirs], theirs)

    def test_bit_packing(self):
        rows = [[0] * 33 for _ in range(2)]
        rows[0][0] = rows[0][31] = rows[0][32] = rows[1][0] = rows[1][32] = 1
        width, height, words = wire.pack_rows(rows)
        # i = y * 33 + x: bits 0, 31 | 32, 33 | 65 -> word 0 bits 0, 31; word 1 bits 0, 1;
        # word 2 bit 1.
        self.assertEqual((width, height), (33, 2))
        self.assertEqual(words, [1 | 1 << 31, 0b11, 0b10])
        with self.assertRaises(ValueError):
            wire.pack_rows([[0, 0], [0]])


class AgainstServer(unittest.TestCase):
    @classmethod
    def setUpClass(cls):
        cls.client = pc.PlannerClient(PREFIX, open_timeout=5.0)
        cls.addClassCleanup(cls.client.close)
        cls.rows = warehouse()
        cls.info = cls.client.upload_map(1, cls.rows)

    def plan(self, start, goal, algorithm="astar", **kwargs):
        """Plans on map 1 (tests upload other maps too)."""
        return self.client.plan(start, goal, algorithm, **{"map_id": 1, **kwargs})

    def blocked(self, x, y):
        return not (0 <= y < len(self.rows) and 0 <= x < len(self.rows[0])) or self.rows[y][x]

    def test_upload_reports_the_map(self):
        self.assertEqual((self.info.width, self.info.height), (37, 23))
        self.assertEqual(self.info.max_cells, self.client.max_cells)

    def test_every_cell_arrives_as_packed(self):
        """A start on a blocked cell is StartOccupied, on a free one a 1-point path."""
        for y, row in enumerate(self.rows):
            for x, cell in enumerate(row):
                if cell:
                    with self.assertRaises(pc.StartOccupied, msg=(x, y)):
                        self.plan((x, y), (x, y))
                else:
                    self.assertEqual(self.plan((x, y), (x, y)).waypoints[0], (x, y))

    def test_astar_path_is_valid(self):
        start, goal = (0, 0), (36, 22)
        r = self.plan(start, goal, "astar")
        pts = r.waypoints
        self.assertEqual((pts[0], pts[-1]), (start, goal))
        length = 0.0
        for (x0, y0), (x1, y1) in zip(pts, pts[1:]):
            dx, dy = x1 - x0, y1 - y0
            self.assertTrue(max(abs(dx), abs(dy)) == 1 and dx == int(dx) and dy == int(dy),
                            f"step {(x0, y0)} -> {(x1, y1)}")
            self.assertFalse(self.blocked(int(x1), int(y1)), (x1, y1))
            if dx and dy:  # no corner cutting
                self.assertFalse(self.blocked(int(x0 + dx), int(y0)) or
                                 self.blocked(int(x0), int(y0 + dy)), (x0, y0, x1, y1))
            length += math.hypot(dx, dy)
        self.assertAlmostEqual(r.length, length, places=3)
        self.assertGreater(r.evaluations, 0)
        self.assertGreater(r.time_us, 0)

    def test_tclhho_path_is_valid(self):
        start, goal = (0, 0), (36, 22)
        r = self.plan(start, goal, "tclhho", seed=3)
        a = self.plan(start, goal, "tclhho", seed=3)
        self.assertEqual(r.waypoints, a.waypoints, "same seed, same path")
        pts = r.waypoints
        self.assertEqual((pts[0], pts[-1]), (start, goal))
        for x, y in pts:
            self.assertTrue(-0.5 <= x <= 36.5 and -0.5 <= y <= 22.5, (x, y))
        polyline = sum(math.dist(p, q) for p, q in zip(pts, pts[1:]))
        self.assertAlmostEqual(r.length, polyline, places=2)
        self.assertGreaterEqual(r.length, math.dist(start, goal) - 1e-3)

    def test_planner_errors(self):
        cases = [(pc.GoalOccupied, dict(goal=(3, 2))), (pc.StartOccupied, dict(start=(3, 2))),
                 (pc.StartOutsideMap, dict(start=(-1, 0))),
                 (pc.GoalOutsideMap, dict(goal=(37, 0))),
                 (pc.GoalOutsideMap, dict(goal=(10**12, 0))),
                 (pc.InvalidParameters, dict(radius=float("nan"))),
                 (pc.InvalidParameters, dict(radius=1025.0)),
                 (pc.InvalidParameters, dict(algorithm="tclhho", population=(1 << 24) + 1)),
                 (pc.InvalidParameters, dict(iterations=1 << 40)),
                 (pc.InvalidParameters, dict(guide=7)),
                 (pc.CapacityExceeded, dict(algorithm="tclhho", population=4096)),
                 (pc.UnknownAlgorithm, dict(algorithm=99))]
        for error, kwargs in cases:
            args = {"start": (0, 0), "goal": (36, 22), **kwargs}
            with self.assertRaises(error, msg=kwargs) as caught:
                self.plan(**args)
            self.assertIsInstance(caught.exception, pc.StatusError)
            self.assertEqual(caught.exception.header.status, error.code)
        with self.assertRaises(pc.PlanError):
            self.plan((0, 0), (36, 22), radius=2e9)

    def test_map_errors_and_versions(self):
        c = self.client
        with self.assertRaises(pc.UnknownMap) as caught:
            c.plan((0, 0), (1, 1), map_id=42, version=1)
        self.assertIsInstance(caught.exception, pc.ServiceError)
        with self.assertRaises(pc.UnknownMap):  # a version the server never got
            c.plan((0, 0), (1, 1), map_id=1, version=9)
        # Version 2 of map 2 replaces version 1: planning on 1 is stale.
        c.upload_map(2, [[0] * 5 for _ in range(4)])
        blocked = [[0] * 5 for _ in range(4)]
        blocked[3][4] = 1
        self.assertEqual(c.upload_map(2, blocked).map_version, 2)
        with self.assertRaises(pc.StaleMapVersion):
            c.plan((0, 0), (4, 3), map_id=2, version=1)
        with self.assertRaises(pc.GoalOccupied):
            c.plan((0, 0), (4, 3), map_id=2, version=2)
        with self.assertRaises(pc.StaleMapVersion):  # re-uploading an older version
            c.upload_map(2, blocked, version=1)
        with self.assertRaises(pc.NoValidPath):
            walled = [[0, 1, 0], [1, 1, 0], [0, 0, 0]]
            c.upload_map(3, walled)
            c.plan((0, 0), (2, 2), map_id=3)
        if c.max_cells is not None:
            with self.assertRaises(pc.MapTooLarge):  # refused before sending
                c.publish_map(4, c.max_cells + 1, 1, [0])

    def test_another_client_uploads_above_the_held_version(self):
        """A second client (no uploads of its own) replaces map 6: its frame goes above the
        version the server holds, so it is planned on, not ignored as outdated."""
        open_map = [[0] * 3 for _ in range(3)]
        self.client.upload_map(6, open_map)
        self.client.upload_map(6, open_map)
        blocked = [[0] * 3 for _ in range(3)]
        blocked[2][2] = 1
        with pc.PlannerClient(PREFIX, open_timeout=5.0) as other:
            self.assertEqual(other.held_version(6), 2)
            self.assertEqual(other.upload_map(6, blocked).map_version, 3)
            with self.assertRaises(pc.GoalOccupied):
                other.plan((0, 0), (2, 2))

    def test_timeout_withdraws_the_request(self):
        began = time.monotonic()
        with self.assertRaises(pc.Timeout):
            self.plan((0, 0), (36, 22), "tclhho", population=128,
                      iterations=1 << 20, timeout=0.05)
        self.assertLess(time.monotonic() - began, 1.0)
        # The server cancelled the long plan: the next request is answered at once.
        began = time.monotonic()
        self.plan((0, 0), (36, 22), timeout=2.0)
        self.assertLess(time.monotonic() - began, 2.0)


class NoServerRunning(unittest.TestCase):
    def test_a_service_of_other_types_is_refused(self):
        prefix = f"{PREFIX}-other"
        node = iox2.NodeBuilder.new().create(iox2.ServiceType.Ipc)
        other = (node.service_builder(iox2.ServiceName.new(f"{prefix}/map"))
                 .publish_subscribe(iox2.Slice[ctypes.c_uint8]).create())
        with self.assertRaises(pc.IncompatibleService) as caught:
            pc.PlannerClient(prefix)
        self.assertIn("IncompatibleTypes", str(caught.exception))
        del other, node

    def test_no_server_fails_cleanly_and_creates_nothing(self):
        prefix = f"{PREFIX}-none"
        began = time.monotonic()
        with self.assertRaises(pc.NoServer):
            pc.PlannerClient(prefix)
        with self.assertRaises(pc.NoServer):
            pc.PlannerClient(prefix, open_timeout=0.3)
        self.assertLess(time.monotonic() - began, 3.0)
        self.assertEqual(existing_services(prefix), [])
        # The client created no service: a server starts on that prefix and serves it.
        server = start_server(prefix)
        self.assertEqual(existing_services(prefix), ["map", "plan", "plan-wake"])
        with pc.PlannerClient(prefix, open_timeout=5.0) as client:
            client.upload_map(1, [[0, 0], [0, 0]])
            self.assertEqual(client.plan((0, 0), (1, 1)).waypoints, [(0, 0), (1, 1)])
            stop_server(server)
            # The server is gone: a typed error, not a hang.
            with self.assertRaises((pc.NoServer, pc.ServerShuttingDown)):
                client.plan((0, 0), (1, 1), timeout=2.0)


def _terminated(*_):
    """SIGTERM (e.g. a CI timeout): stop the servers, then exit."""
    for proc in SERVERS:
        stop_server(proc)
    os._exit(1)


if __name__ == "__main__":
    signal.signal(signal.SIGTERM, _terminated)
    result = unittest.main(verbosity=2, exit=False).result
    failed = len(result.failures) + len(result.errors) + len(result.unexpectedSuccesses)
    print(f"{max(result.testsRun - failed - len(result.skipped), 0)} passed, {failed} failed"
          + (f", {len(result.skipped)} skipped" if result.skipped else ""))
    sys.exit(1 if failed or not result.testsRun else 0)

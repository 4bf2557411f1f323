"""PlannerClient: map upload and planning against a running planner-server (docs/wire.md).

The client only opens the services under its prefix; it never creates one (a service
created by a client with other settings would keep the server from starting).
"""

import ctypes
import math
import os
import time
from array import array
from contextlib import suppress
from dataclasses import dataclass

import iceoryx2 as iox2

from . import errors
from .errors import (
    BadResponse, IncompatibleService, IpcError, NoServer, PlannerError, Timeout,
)
from .wire import (
    ALGORITHMS, GUIDES, KIND_MAP_STATUS, KIND_PLAN, LAYOUT_ROWS, MAP_INITIAL_SLICE_LEN,
    WIRE_VERSION, MapHeader, PlanRequest, PlanResponseHeader, Waypoint, pack_rows,
)

MAX_CELLS_ATTRIBUTE = "planner/max-cells"
# iceoryx2's open errors that mean "no server serves this prefix (now)".
_ABSENT = ("DoesNotExist", "IsMarkedForDestruction", "HangsInCreation")


@dataclass(frozen=True)
class PlanResult:
    """A path: `waypoints` [(x, y), ...] in cells, start first."""

    waypoints: list
    length: float
    turns: int
    evaluations: int
    time_us: float  # the server's handling time
    map_id: int
    map_version: int


@dataclass(frozen=True)
class MapInfo:
    """The server holds this map version (a map-status answer)."""

    map_id: int
    map_version: int
    width: int
    height: int
    decode_us: float  # the server's one-time cost of making the version usable
    max_cells: int  # the server's map limit


_OPEN_ERRORS = (iox2.PublishSubscribeOpenError, iox2.RequestResponseOpenError,
                iox2.EventOpenError)


def _open(what, name, builder):
    try:
        return builder.open()  # never open_or_create: the server creates the services
    except _OPEN_ERRORS as e:  # args[0] names the cause, e.g. "DoesNotExist"
        cause = str(e.args[0]) if e.args else repr(e)
        if any(cause.startswith(a) for a in _ABSENT):
            raise NoServer(f"no planner-server serves {name!r} ({cause})") from None
        raise IncompatibleService(f"cannot open {what} {name!r}: {cause}") from None


class PlannerClient:
    """One connection to the planner service under `prefix` (one request at a time).

    Raises NoServer when the services do not exist; with `open_timeout` > 0 it retries
    until then (for a server that is starting).
    """

    def __init__(self, prefix="planner", *, open_timeout=0.0, spin=0.002,
                 node_name="planner-client-py"):
        self.prefix = prefix
        self.spin = spin  # seconds of yielding polls before short sleeps
        self._versions = {}  # map id -> last version published by this client
        self._next_id = 1
        self._last_map = None
        self._publisher = self._client = self._wake = None
        iox2.set_log_level_from_env_or(iox2.LogLevel.Error)
        self._node = (iox2.NodeBuilder.new().name(iox2.NodeName.new(node_name))
                      .signal_handling_mode(iox2.SignalHandlingMode.Disabled)
                      .create(iox2.ServiceType.Ipc))
        deadline = time.monotonic() + open_timeout
        while True:
            try:
                self._open_ports()
                return
            except NoServer:
                if time.monotonic() >= deadline:
                    self.close()
                    raise
                time.sleep(0.01)

    def _open_ports(self):
        node, p = self._node, self.prefix
        svc = lambda suffix: node.service_builder(iox2.ServiceName.new(f"{p}/{suffix}"))
        map_service = _open("map service", f"{p}/map", svc("map")
                            .publish_subscribe(iox2.Slice[ctypes.c_uint32])
                            .user_header(MapHeader))
        plan_service = _open("plan service", f"{p}/plan", svc("plan")
                             .request_response(PlanRequest, iox2.Slice[Waypoint])
                             .response_header(PlanResponseHeader))
        wake_service = _open("wake event", f"{p}/plan-wake", svc("plan-wake").event())
        values = map_service.attributes.key_values(iox2.AttributeKey.new(MAX_CELLS_ATTRIBUTE))
        self.max_cells = int(values[0].to_string()) if values else None
        try:
            self._publisher = (map_service.publisher_builder()
                               .initial_max_slice_len(MAP_INITIAL_SLICE_LEN)
                               .allocation_strategy(iox2.AllocationStrategy.PowerOfTwo)
                               .max_loaned_samples(1)
                               .create())
            self._client = plan_service.client_builder().create()
            self._wake = wake_service.notifier_builder().create()
        except (iox2.PublisherCreateError, iox2.ClientCreateError,
                iox2.NotifierCreateError) as e:  # e.g. the service's port limits
            self.close()
            raise IpcError(f"cannot create a port under {p!r}: {e!r}") from None
        self._services = (map_service, plan_service, wake_service)

    def close(self):
        """Releases the ports and the node (the published maps leave the history)."""
        for port in ("_wake", "_client", "_publisher"):
            if getattr(self, port, None) is not None:
                getattr(self, port).delete()
                setattr(self, port, None)
        self._services = self._node = None

    def __enter__(self):
        return self

    def __exit__(self, *exc):
        self.close()

    # Maps

    def upload_map(self, map_id, rows, *, version=None, resolution=1.0, origin=(0.0, 0.0),
                   timeout=5.0):
        """Publishes `rows` (equal-length rows, truthy = blocked; (0, 0) is the upper-left
        cell) as `map_id` at `version` (default: this client's last version + 1) and waits
        until the server holds it. Returns MapInfo; raises MapTooLarge over the server's
        limit, StaleMapVersion when the server holds a newer version, Timeout."""
        width, height, words = pack_rows(rows)
        version = self.publish_map(map_id, width, height, words, version=version,
                                   resolution=resolution, origin=origin)
        return self.wait_for_map(map_id, version, timeout)

    def publish_map(self, map_id, width, height, words, *, version=None, layout=LAYOUT_ROWS,
                    resolution=1.0, origin=(0.0, 0.0)):
        """Publishes a frame of packed words as is (wire.pack_rows); returns its version."""
        if self.max_cells is not None and width * height > self.max_cells:
            raise errors.MapTooLarge(detail=f"map {width} x {height} exceeds the server's "
                                     f"limit of {self.max_cells} cells (not sent)")
        if self._publisher is None:
            raise PlannerError("the client is closed")
        if version is None:
            # Above the server's and our own: a frame at or below what the server holds is
            # ignored as outdated.
            version = max(self._versions.get(map_id, 0), self.held_version(map_id)) + 1
        sample = self._publisher.loan_slice_uninit(len(words))
        (ctypes.c_uint32 * len(words)).from_address(sample.payload_ptr)[:] = words
        header = sample.user_header().contents
        header.wire_version, header.layout, header.reserved = WIRE_VERSION, layout, 0
        header.map_id, header.map_version = map_id, version
        header.width, header.height = width, height
        header.resolution, header.origin[:] = resolution, origin
        sample.assume_init().send()
        self._versions[map_id] = version
        self._last_map = (map_id, version)
        return version

    def wait_for_map(self, map_id, version, timeout=5.0):
        """Asks the server (map-status requests) until it holds `map_id` at `version`."""
        deadline = time.monotonic() + timeout
        while True:
            try:
                left = max(deadline - time.monotonic(), 0.001)
                return self.map_status(map_id, version, timeout=left)
            except (errors.UnknownMap, NoServer) as e:  # not there yet, or a server starting
                if time.monotonic() >= deadline:
                    raise Timeout(f"the server did not take map {map_id} version {version} "
                                  f"within {timeout} s ({type(e).__name__})") from None
                time.sleep(0.001)

    def held_version(self, map_id, *, timeout=1.0):
        """The newest version of `map_id` the server holds (0: none, or no server)."""
        try:
            h, _ = self._call(PlanRequest(wire_version=WIRE_VERSION, kind=KIND_MAP_STATUS,
                                          map_id=map_id, map_version=0), timeout)
        except errors.StatusError as e:  # version 0 is never held: the answer says which is
            h = e.header
        except (NoServer, Timeout):
            return 0
        return h.held_version if h is not None else 0

    def map_status(self, map_id, version, *, timeout=1.0):
        """One map-status request: MapInfo, or the map's error (UnknownMap, ...)."""
        request = PlanRequest(wire_version=WIRE_VERSION, kind=KIND_MAP_STATUS,
                              map_id=map_id, map_version=version)
        h, _ = self._call(request, timeout)
        return MapInfo(map_id, version, h.map_width, h.map_height, h.map_decode_us, h.max_cells)

    # Planning

    def plan(self, start, goal, algorithm="astar", *, map_id=None, version=None, seed=0,
             radius=0.0, population=0, iterations=0, stagnation=0, guide="anyangle",
             deadline_us=0, timeout=5.0):
        """Plans from `start` to `goal` (cells (x, y)) on `map_id` at `version` (default:
        the map this client uploaded last). `algorithm` is a name (wire.ALGORITHMS) or a
        code. Returns PlanResult or raises a PlannerError (a StatusError subclass per
        status code, NoServer, Timeout, BadResponse)."""
        if map_id is None:
            if self._last_map is None:
                raise ValueError("no map uploaded by this client: pass map_id and version")
            map_id, last = self._last_map
            version = last if version is None else version
        elif version is None:
            version = self._versions.get(map_id)
            if version is None:
                raise ValueError(f"map {map_id} was not uploaded by this client: pass version")
        code = _code(ALGORITHMS, algorithm, "algorithm")
        request = PlanRequest(wire_version=WIRE_VERSION, kind=KIND_PLAN, algorithm=code,
                              seed=seed, deadline_us=deadline_us,
                              map_id=map_id, map_version=version)
        request.start[:] = [_i32(v) for v in start]
        request.goal[:] = [_i32(v) for v in goal]
        p = request.params
        p.radius = radius
        p.population, p.iterations, p.stagnation = (
            _u32(population), _u32(iterations), _u32(stagnation))
        p.guide = _code(GUIDES, guide, "guide")
        h, waypoints = self._call(request, timeout)
        return PlanResult(waypoints, h.length, h.turns, h.evaluations, h.time_us,
                          map_id, version)

    def _call(self, request, timeout):
        """Sends `request`, wakes the server, polls for the answer until `timeout`:
        returns (a copy of the response header, waypoints)."""
        if self._client is None:
            raise PlannerError("the client is closed")
        request.request_id = self._next_id
        self._next_id += 1
        began = time.perf_counter()
        try:
            pending = self._client.send_copy(request)
        except (iox2.RequestSendError, iox2.LoanError) as e:
            raise IpcError(f"cannot send the request: {e!r}") from None
        try:
            if pending.number_of_server_connections == 0:
                raise NoServer(f"no planner-server is connected to {self.prefix}/plan")
            with suppress(iox2.NotifierNotifyError):  # else the server's 50 ms tick
                self._wake.notify()  # a blocking server sleeps on P/plan-wake
            nap = 20e-6
            while (response := _receive(pending)) is None:
                now = time.perf_counter()
                if now - began >= timeout:
                    raise Timeout(f"no answer within {timeout} s")
                if now - began < self.spin:
                    os.sched_yield()  # a server on this core gets to run (sleep(0) sleeps ~50 us)
                else:
                    time.sleep(min(nap, timeout - (now - began)))
                    nap = min(2 * nap, 1e-3)
            try:
                return _decode(request, response)
            finally:
                response.delete()
        finally:
            pending.delete()  # before an answer: withdraws the request


def _decode(request, response):
    h = PlanResponseHeader.from_buffer_copy(response.user_header().contents)
    if h.request_id != request.request_id:
        raise BadResponse(f"answer to request {h.request_id}, expected {request.request_id}")
    if h.wire_version != WIRE_VERSION or h.kind != request.kind:
        raise BadResponse(f"wire version {h.wire_version}, kind {h.kind}")
    if h.status != 0:
        cls = errors.STATUS_ERRORS.get(h.status)
        if cls is None:
            raise BadResponse(f"unknown status {h.status}")
        raise cls(h)
    # iceoryx2 issue 1533: in the Python binding 0.10.0 Slice.len() counts bytes.
    n, nbytes = h.waypoints, response.payload().len()
    if nbytes != n * ctypes.sizeof(Waypoint):
        raise BadResponse(f"{n} waypoints in the header, {nbytes} bytes in the slice")
    floats = array("f", ctypes.string_at(response.payload_ptr, nbytes))
    if not all(map(math.isfinite, floats)) or not math.isfinite(h.length):
        raise BadResponse("a number in the answer is not finite")
    it = iter(floats)
    return h, list(zip(it, it))


def _receive(pending):
    try:
        return pending.receive()
    except iox2.ReceiveError as e:
        raise IpcError(f"cannot receive the answer: {e!r}") from None


def _code(names, value, what):
    """A u8 wire code from a name, or a code as is (a server rejects unknown ones)."""
    if not isinstance(value, str):
        if not 0 <= value <= 255:
            raise ValueError(f"{what} code {value} is not a u8")
        return value
    if value not in names:
        raise ValueError(f"unknown {what} {value!r}; known: {', '.join(names)}")
    return names[value]


def _i32(v):
    """A cell coordinate, clamped to i32 (anything beyond is outside every map)."""
    return max(-(1 << 31), min(int(v), (1 << 31) - 1))


def _u32(v):
    """A count; outside u32 it is sent as u32::MAX, so that the server answers
    InvalidParameters (ctypes would wrap it silently)."""
    v = int(v)
    return v if 0 <= v < (1 << 32) else (1 << 32) - 1

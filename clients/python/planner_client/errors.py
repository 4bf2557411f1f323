"""The client's exceptions: one class per status code (docs/wire.md, Codes), plus the
client's own failures. Catch `PlannerError` for all of them."""


class PlannerError(Exception):
    """Base of every error this client raises."""


class NoServer(PlannerError):
    """No planner-server serves this prefix (its services do not exist, or no server is
    connected)."""


class Timeout(PlannerError):
    """No answer within the timeout; the request was withdrawn (the server skips it)."""


class BadResponse(PlannerError):
    """A malformed answer: unknown status, wrong request id or wire version, a waypoint
    slice that disagrees with the header, a number that is not finite."""


class IpcError(PlannerError):
    """iceoryx2 failed (a port could not be created, a request could not be sent)."""


class IncompatibleService(IpcError):
    """A service exists under the prefix but iceoryx2 refused to open it (another wire
    version's types, or settings this client cannot use)."""


class StatusError(PlannerError):
    """The server answered with a status other than ok. `header` is a copy of the answer's
    PlanResponseHeader (map size, times and the server's `max_cells` included)."""

    code = -1

    def __init__(self, header=None, detail=None):
        self.header = header
        super().__init__(detail or f"{type(self).__name__} (status {self.code})")


class PlanError(StatusError):
    """The planner could not plan (Nav2-like codes 1-8)."""


class StartOutsideMap(PlanError): code = 1
class GoalOutsideMap(PlanError): code = 2
class StartOccupied(PlanError): code = 3
class GoalOccupied(PlanError): code = 4
class NoValidPath(PlanError): code = 5
class CapacityExceeded(PlanError): code = 6
class InvalidParameters(PlanError): code = 7
class BudgetExhausted(PlanError): code = 8


class ServiceError(StatusError):
    """The service refused the request (codes 101-110)."""


class UnknownMap(ServiceError): code = 101
class StaleMapVersion(ServiceError): code = 102
class MapTooLarge(ServiceError): code = 103
class UnknownAlgorithm(ServiceError): code = 104
class InvalidRequest(ServiceError): code = 105
class Cancelled(ServiceError): code = 106
class ServerShuttingDown(ServiceError): code = 107
class DeadlineExceeded(ServiceError): code = 108
class Internal(ServiceError): code = 109
class UnsupportedVersion(ServiceError): code = 110


# Status code -> exception class.
STATUS_ERRORS = {cls.code: cls for base in (PlanError, ServiceError)
                 for cls in base.__subclasses__()}

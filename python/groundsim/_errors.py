"""The exceptions of groundsim; the C++ errors are translated into these."""

from typing import NamedTuple, Sequence, Tuple


class ExperimentError(ValueError):
    __module__ = "groundsim"
    """A bad call: wrong shapes or dtypes, NaN actions, a seed or env index
    out of range, a snapshot of another scenario or a corrupted one.

    ``field`` names what is wrong, e.g. ``"actions"``, ``"actions[3][1]"``,
    ``"seed"``, ``"env"``, ``"snapshot"``."""

    def __init__(self, field: str, message: str):
        super().__init__(message)
        self.field = field

    def __reduce__(self):
        return (type(self), (self.field, str(self)))


class ScenarioIssue(NamedTuple):
    path: str     # JSON pointer into the scenario, "" for the document
    message: str  # the reason


class ScenarioError(ValueError):
    __module__ = "groundsim"
    """A scenario (or its task section) that does not validate. ``issues``
    lists every problem found (at most 20) with its JSON pointer; ``omitted``
    counts those beyond."""

    def __init__(self, message: str, issues: Sequence[Tuple[str, str]] = (), omitted: int = 0):
        super().__init__(message)
        self.issues = [ScenarioIssue(*issue) for issue in issues]
        self.omitted = omitted

    def __reduce__(self):
        return (type(self), (str(self), [tuple(i) for i in self.issues], self.omitted))


class RemoteError(ConnectionError):
    __module__ = "groundsim"
    """The server of a make_remote_vec environment cannot be reached or
    stopped answering: no heartbeat, no reply, or parts of a reply missing
    (named in the message). Never a silently short result."""

"""The one status enumeration of every compiled run, with a message per code.

Every kernel that reports how a run ended (the general engine's fixed and adaptive steppers and
its map with tangents, the continuous shaft's steppers, its stroboscopic and Lyapunov maps, the
free-speed integrator, the banded linear sweeps) leaves one of these codes. They are plain
``int`` module constants so that numba freezes them into the compiled code; :class:`Status`
mirrors them as an :class:`enum.IntEnum` and :data:`MESSAGES` (indexed by code) says what each
means, so a result can carry the code and its message.

Codes (the first four kept the values the engines used before the enumeration was shared):

``OK`` (0)
    The run completed.
``DIVERGED`` (1)
    A displacement left the divergence bound (or became NaN).
``CONTACT_FAILED`` (2)
    The implicit contact solve did not converge (at the finest sub-step where the stepper halves
    its step).
``EVENT_BUFFER_FULL`` (3)
    The contact event buffer had too little room: the driver grows it and resumes, or stops when
    events were lost.
``STEP_TOO_SMALL`` (4)
    An adaptive step fell below its floor.
``MAX_STEPS`` (5)
    The step budget ran out.
``SINGULAR`` (6)
    A matrix to factorise was singular (a zero pivot).
``TANGENTS_DEGENERATE`` (7)
    Tangent vectors lost their independence (a zero norm at re-orthonormalisation).
``INTERRUPTED`` (8)
    The user stopped the run (Ctrl-C) between two chunks of samples; what was computed is kept.
"""

from enum import IntEnum

__all__ = [
    "OK",
    "DIVERGED",
    "CONTACT_FAILED",
    "EVENT_BUFFER_FULL",
    "STEP_TOO_SMALL",
    "MAX_STEPS",
    "SINGULAR",
    "TANGENTS_DEGENERATE",
    "INTERRUPTED",
    "MESSAGES",
    "Status",
    "message",
    "I_STEP",
    "I_EVENTS",
    "I_STATUS",
]

OK = 0
DIVERGED = 1
CONTACT_FAILED = 2
EVENT_BUFFER_FULL = 3
STEP_TOO_SMALL = 4
MAX_STEPS = 5
SINGULAR = 6
TANGENTS_DEGENERATE = 7
INTERRUPTED = 8

MESSAGES = (
    "complete",
    "diverged",
    "contact solve failed",
    "event buffer full",
    "step size too small",
    "too many steps",
    "singular matrix",
    "tangent vectors degenerate",
    "interrupted by the user",
)
"""What each code means, indexed by the code."""


class Status(IntEnum):
    """The status codes as an enumeration (``Status(code).message`` says what it means)."""

    OK = OK
    DIVERGED = DIVERGED
    CONTACT_FAILED = CONTACT_FAILED
    EVENT_BUFFER_FULL = EVENT_BUFFER_FULL
    STEP_TOO_SMALL = STEP_TOO_SMALL
    MAX_STEPS = MAX_STEPS
    SINGULAR = SINGULAR
    TANGENTS_DEGENERATE = TANGENTS_DEGENERATE
    INTERRUPTED = INTERRUPTED

    @property
    def message(self) -> str:
        """What the code means."""
        return MESSAGES[self.value]


def message(code: int) -> str:
    """What status ``code`` means (``"unknown status <code>"`` for a code outside the table)."""
    code = int(code)
    return MESSAGES[code] if 0 <= code < len(MESSAGES) else f"unknown status {code}"


I_STEP, I_EVENTS, I_STATUS = 0, 1, 2
"""Slots every stepper's integer state ``istate`` shares: steps taken (or saved samples),
contact events counted, and the status code."""

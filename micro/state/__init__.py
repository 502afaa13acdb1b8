"""A collapse state as data: write it, read it, verify it (``xcheck micro --state``, ``xcheck verify``).

``data``   the state (:class:`CollapseStateData`) and the state behind a result (:func:`collapse_state`);
``file``   its JSON format (:func:`write_state`, :func:`read_state`; the format in its docstring and in
           ``docs/schemas/state.schema.json``);
``check``  the check (:func:`verify_state` gives a :class:`StateCheck`) from nothing but the state's own
           data, so that another program's state is checked as this library's is.
"""

from micro.state.check import Residual, StateCheck, verify_state
from micro.state.data import CollapseStateData, collapse_state
from micro.state.file import StateFileError, parse_state, read_state, write_state

__all__ = ["CollapseStateData", "Residual", "StateCheck", "StateFileError", "collapse_state", "parse_state",
           "read_state", "verify_state", "write_state"]

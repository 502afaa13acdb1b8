"""A collapse state as data: write it, read it, verify it against the wall it names (``xcheck micro --state``,
``xcheck verify``).

``data``       the state (:class:`CollapseStateData`) and the state behind a result (:func:`collapse_state`);
``structure``  its bodies (a block, or a block with the blocks held to it), their outlines and loads, and the
               wall that builds it (:class:`WallParameters`);
``file``       its JSON format (:func:`write_state`, :func:`read_state`; the format in its docstring and in
               ``docs/schemas/state.schema.json``), read through ``document`` and ``jsontext``;
``check``      the check (:func:`verify_state` gives a :class:`StateCheck`): the wall (``rebuild``), the
               geometry and loads (``outlines``) and the flow rule (``mechanics``), each residual relative to
               the block or point it is at, so that another program's state is checked as this library's is.
"""

from micro.state.data import CollapseStateData, collapse_state
from micro.state.document import StateFileError
from micro.state.file import parse_state, read_state, write_state
from micro.state.structure import WallParameters
from micro.state.verify import Residual, StateCheck, verify_state

__all__ = ["CollapseStateData", "Residual", "StateCheck", "StateFileError", "WallParameters", "collapse_state",
           "parse_state", "read_state", "verify_state", "write_state"]

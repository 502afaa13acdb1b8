"""The descent from the iterated LP's fixed point to the lowest certified collapse state.

:mod:`.lowest` walks from state to state (:func:`~.lowest.lowest_state`);
:mod:`.states` holds the two LPs of a contact pattern it runs on (the least
load factor, a compatible mechanism); :mod:`.lowest_direction` its result type,
:class:`~.results.LowestDirection`. It reads the iterated LP's result and
model, and the certificate's reading of a mechanism
(:func:`micro.nonassociative.certificate.point_states`); the iterated LP does
not import it: :func:`micro.solve_nonassociative` composes the two.
"""

"""Every reader recipe of contactres in one immutable registry (:data:`ALL_READERS`), now
composed in :mod:`contactres.jobs.readers` (the lowest layer that sees every format, the value
grids of the map jobs included): re-exported here for the code written against
``contactres.apps.readers``.

>>> from contactres.apps.readers import ALL_READERS
>>> [r.name for r in ALL_READERS.of_kind("ebsd")]
['ang', 'ctf']
"""

from ..jobs.readers import ALL_READERS, GRID_READER

__all__ = ["ALL_READERS", "GRID_READER"]

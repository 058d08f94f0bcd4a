"""The notices written into every synthetic folder: what marks data as made, not measured.

Kept apart from the generator so that a job which only asks "is this the
reconstruction?" (the article's) does not depend on the generator's code.
"""

from __future__ import annotations

__all__ = ["DATA_NOTICE", "PHOTOGRAPH_NOTICE"]

#: Written as NOTICE.txt into every generated folder; its first line becomes the
#: footer of each figure and table built from these data.
DATA_NOTICE = (
    "Synthetic reconstruction made by a seeded generator; not the original measurements "
    "of Srinivasan (1989).\n"
    "The study's digitised profiles were never published. See data/README.md for how these "
    "files were made.\n"
)

#: Written as NOTICE.txt into the photograph example's folder.
PHOTOGRAPH_NOTICE = (
    "Synthetic photographs rendered by a seeded generator from the reconstruction's true "
    "profiles; not photographs of fingers.\n"
    "See data/README.md for how they are made.\n"
)

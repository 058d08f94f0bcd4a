"""Raw data in: the data contract's checks and the conversion of photographs and readings.

Importing this package, :mod:`~lineload.rawdata.errors` or
:mod:`~lineload.rawdata.validation` imports nothing heavy (numpy is imported when a
check first needs it), so Snakemake can read the subject sheet when it parses the
workflow; :mod:`~lineload.rawdata.photographs` imports numpy and scikit-image.

Modules
-------
validation
    The contract's rules that span rows and files, and :func:`check_dataset` running
    every check on a raw folder; re-exports the checks of the modules below.
errors
    :class:`InputError`, the :class:`Problems` collector and how a refused run is
    reported (standard library only).
sheets
    Reading one table against its row schema: encodings, separators, headers, cells.
plausibility
    Magnitudes a fingertip can have: depths, deflections, lengths (unit mistakes named).
forces
    The optional ``forces.csv``.
images
    ``images/images.csv`` and the photograph pairs it names.
paths
    Links leading out of the raw folder; names that nearly match the contract's.
photographs
    A subpackage: reading a skin outline from a pair of photographs (before and under
    the wedge): the files, the edges, glare, the wedge's apex, the stated
    uncertainties and the pair read into readings, one module each.
digitising
    A batch of photographed subjects read pair by pair, as rule ``digitise`` does.
readings
    Digitised readings of the print to tissue millimetres.
"""

from lineload.rawdata.errors import InputError, Problems, report_lines

__all__ = ["InputError", "Problems", "report_lines"]

"""Raw data in: the data contract's checks and the conversion of photographs and readings.

Modules
-------
validation
    Checks of the raw-data contract; every problem names its file, row, column and subject.
photographs
    Reading a skin outline from a pair of photographs (before and under the wedge).
readings
    Digitised readings of the print to tissue millimetres.
"""

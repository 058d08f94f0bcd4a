"""Simulated data: the shipped reconstruction and the studies that calibrate the verdicts.

Import the module you need; this package imports none of them (so a job that needs
one part does not depend on the rest).

Modules
-------
synthetic
    The generator's public face: every name below that makes the shipped data.
subjects
    The synthetic fingers, their true profiles and their random streams.
errors
    The forward error model: what digitising adds to a true profile (the generator's
    and the coverage study's), and the size of every error.
readings
    The profiles, outlines and forces of the reconstruction, as read.
dataset
    The files of the raw-data folder, the tables of true parameters, the built-in verdicts.
notices
    The notices that mark a generated folder as synthetic.
photograph_render
    Side views of a finger as a camera takes them (the example's and the digitiser
    calibration's renderer).
photograph_example
    The photograph example (two fingers photographed at rest and loaded).
coverage
    How often the intervals hold the truth on data made with known parameters.
analysis
    A simulated dataset analysed as the rule scripts analyse a real one, in memory
    (averaged, noise measured, the paper's models fitted, claims judged); its truth
    judged with the noise shrunk to nothing.
calibration
    The verdict calibration's public face: every name of the four modules below.
verdicts
    How often each claim's rule reaches the right verdict on reconstructions with fresh
    errors, analysed with the functions the rule scripts call.
boundary
    The boundary worlds: each claim's rule where it has the least power.
mechanics_coverage
    Coverage of the membrane's intervals on the verdict calibration's datasets.
reports
    The calibration's tables as Markdown, each with the command that made it.
elastic_world
    A world the fits do not assume: the finite-element finger (homogeneous and layered)
    read with the digitising errors; the paper's models' intervals, the claims' verdicts
    and the layered fit's modulus ratio scored there (docs/calibration/elastic_world.md).
rates
    Binomial (Clopper-Pearson) intervals and the error-rate sentences of the claims
    table; light, so the claims table does not depend on the generator.
"""

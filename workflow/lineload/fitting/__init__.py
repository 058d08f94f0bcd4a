"""Fitting the models to the averaged profiles, one trial or a whole batch at a time.

Modules
-------
batch
    The batch engine: windows, weights and the three fits of the paper for every trial.
optimize
    The bounded one-parameter least-squares solver shared by every fit.
bending
    Fits of the bending skin (tension with bending stiffness).
sensitivity
    Refits under other choices (windows, weights, models) to show what each choice moves.
"""

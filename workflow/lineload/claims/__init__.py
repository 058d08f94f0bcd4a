"""The claims table: each statement of the paper as a test on the fits, with its verdict.

Modules
-------
rules
    Every claim's rule, its text and the table they make.
"""

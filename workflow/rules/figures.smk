# Stage 3, figures: the paper's Figures 1-7 and the supplementary figures.

# Every figure file the default target builds (PDF and PNG of each).
FIGURE_OUTPUTS = []

# Stage 4, tables: fit tables in CSV/Markdown/LaTeX, species summary, claims.

# Every table file the default target builds.
TABLE_OUTPUTS = []

# The elastic fingertip's solution library (not part of the default build): the
# finite-element finger solved over its grid (config elastic), one job per
# species, gathered into one table. Minutes on two cores; the table is kept in the
# repository (data/elastic/library.csv), from which the default build's elastic_fits
# reads. Build with `snakemake --cores 2 elastic_library`.

ELASTIC_SPECIES = ["monkey", "human"]


rule elastic_library_species:
    """Solve one species' finger over the library's grid: every section, layer thickness
    and modulus ratio, the depths on one factorisation each."""
    input:
        code=code("build_elastic_library.py"),
    output:
        temp(result("elastic", "library_{species}.csv")),
    log:
        result("logs", "elastic_library", "{species}.log"),
    benchmark:
        result("benchmarks", "elastic_library", "{species}.tsv")
    wildcard_constraints:
        species="|".join(ELASTIC_SPECIES),
    conda:
        ENVIRONMENT
    params:
        species=lambda wildcards: wildcards.species,
        grid={k: v for k, v in config["elastic"].items() if k != "library_file"},
    script:
        "../scripts/build_elastic_library.py"


rule elastic_library:
    """The elastic finger's solution library, both species in one table."""
    input:
        tables=expand(rules.elastic_library_species.output[0], species=ELASTIC_SPECIES),
        code=code("concat_tables.py"),
    output:
        result("elastic", "library.csv"),
    log:
        result("logs", "elastic_library.log"),
    benchmark:
        result("benchmarks", "elastic_library.tsv")
    conda:
        ENVIRONMENT
    script:
        "../scripts/concat_tables.py"

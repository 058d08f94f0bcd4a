# Stage 6, article: the reproduction written by the workflow from its own results.


rule article:
    """Typeset the reproduction article (Typst) from the results tables and figures."""
    input:
        **article_inputs(),
    output:
        pdf=report_item(
            result("article", "reproduction.pdf"),
            caption="../report/article.rst",
            category="Article",
            labels={"document": "the reproduction, as an article"},
        ),
        facts=result("article", "facts.json"),
        source=result("article", "reproduction.typ"),
    log:
        result("logs", "article.log"),
    benchmark:
        result("benchmarks", "article.tsv")
    conda:
        ENVIRONMENT
    script:
        "../scripts/write_article.py"

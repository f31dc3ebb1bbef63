# Two commands do everything on a fresh machine with Python 3.11 and pip:
#   make reproduce   -- regenerate the paper's figures, tables and summary under results/ (paper and
#                       physical modes, and their comparison results/comparison.md)
#   make test        -- run the test suite
#   make docs        -- build the documentation site into site/ (mkdocs, --strict)
PYTHON ?= python3.11
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
CLUSTER_STAMP := $(VENV)/.installed-cluster
# make test runs the suite on this many pytest-xdist workers (auto: one per CPU; TEST_WORKERS=0 runs
# it in one process). The tests that read the session's quick runs form one work unit, every other
# module one unit of its own (tests/conftest.py).
TEST_WORKERS ?= auto
XDIST := -n $(TEST_WORKERS) --dist loadscope --no-loadscope-reorder


.PHONY: test-fast
.PHONY: venv test docs test-docs-browser reproduce reproduce-extra resume reproduce-quick update-references clean-venv cluster-venv test-slurm report

# Re-install whenever pyproject.toml changes (the stamp is older than it).
$(STAMP): pyproject.toml
	test -x $(BIN)/python || $(PYTHON) -m venv $(VENV)
	$(BIN)/python -m pip install --quiet --upgrade pip
	$(BIN)/python -m pip install --quiet -e '.[test,docs]'
	touch $(STAMP)

venv: $(STAMP)

test: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/lint-imports
	$(BIN)/python -m pytest -q $(XDIST)

# The same checks without the tests that run whole Snakemake studies or build the wheel (minutes
# instead of tens of minutes on a 2-core machine): for the edit-test loop, not for CI.
test-fast: $(STAMP)
	$(BIN)/ruff check .
	$(BIN)/ruff format --check .
	$(BIN)/lint-imports
	$(BIN)/python -m pytest -q $(XDIST) -m "not slow" --ignore=tests/test_workflow.py --ignore=tests/test_workflow_spatial.py --ignore=tests/test_own_design.py --ignore=tests/test_package.py \
		--ignore=tests/pipeline/test_shell.py --ignore=tests/test_cluster_profile.py

# The documentation site (docs/, mkdocs.yml): every warning is an error.
docs: $(STAMP)
	$(BIN)/mkdocs build --strict -d site

# The site in headless Chromium: equations rendered offline by the vendored MathJax, no MathJax
# error (tests/docs/test_docs_browser.py; skipped with a message where no browser is installed:
# Debian `apt-get install chromium`).
test-docs-browser: $(STAMP)
	CDPR_DOCS_BROWSER=1 $(BIN)/python -m pytest -q tests/docs/test_docs_browser.py

# Every tracked output is recomputed (--forceall): a fresh clone's tracked results are never reused.
# The paper study (results/paper), the same study in physical mode (results/physical: the platform
# on all cables, config/studies/physical.yaml differs only in name and redundancy), the studies of
# the reproduce-extra hook, then their comparison and the error budget (results/comparison.md and
# results/comparison/; config/comparisons/paper_vs_physical.yaml).
# The paper and physical studies write disjoint folders and read none of each other's files: they
# run side by side, one core each (Snakemake scales each solver job's threads down to 1; the tables
# do not depend on the thread count), the calibration studies and the Hangprinter study (real
# data, results/hangprinter) after the paper study on its core, the large study (results/large)
# after the physical study on the other (the physical stream finished 2-3 min earlier).
# On 2 cores that keeps both cores busy, where one 2-thread solver job at a time left part of them
# idle (benchmarks/README.md). Both streams finish before the CoGiRo study, whose conclusions read
# results/physical; a failure in either stops make with its exit status.
PHYSICAL := --config study=config/studies/physical.yaml results=results/physical
COMPARISON_RULES := budget_design budget comparison
# the six short budget_design jobs (4-5 s each, a third of it start-up) one thread each, two at a
# time on 2 cores: with the study's solver_threads (2) they ran one after the other
COMPARISON_THREADS := --set-threads budget_design=1
REPRODUCE_CALIBRATION := calibration_study calibration_cogiro hangprinter_study
REPRODUCE_COGIRO := --config study=config/studies/cogiro.yaml results=results/cogiro
# the large study (issue 38, config/studies/large.yaml): only its `large_study` target (plane maps and
# the path with and without sag, what sag adds, the catenaries at a corner pose; workflow/rules/large.smk),
# measured 56 s wall on one core at load 8-11 (17 s user CPU; a first run with cold caches 107 s)
# numba compiles a kernel the first time a process calls it (cached in cdpr/compiled/__pycache__
# afterwards): on a fresh clone the two streams compiled the same point-mass kernels at once and the
# CoGiRo study's two budget jobs the same rigid-platform ones. `cdpr compile` compiles each family
# once, on the stream that needs it first: paper-mode kernels on one core while the physical ones
# compile on the other, the rigid-platform and heavy-cable ones before the calibration studies (and
# so before the CoGiRo study). With a warm cache each takes a second.
COMPILE := $(BIN)/python -m cdpr compile --part
REPRODUCE_LARGE := large_study --config study=config/studies/large.yaml results=results/large
reproduce: $(STAMP)
	( $(COMPILE) paper && $(BIN)/snakemake --cores 1 --forceall reproduce_paper && \
	  $(COMPILE) platform heavy && $(BIN)/snakemake --cores 1 --forceall $(REPRODUCE_CALIBRATION) ) & paper=$$!; \
	( $(COMPILE) physical && $(BIN)/snakemake --cores 1 --forceall reproduce_paper $(PHYSICAL) && \
	  $(BIN)/snakemake --cores 1 --forceall $(REPRODUCE_LARGE) ) & physical=$$!; \
	wait $$paper; a=$$?; wait $$physical; b=$$?; test $$a -eq 0 && test $$b -eq 0
	$(BIN)/snakemake --cores all --forceall reproduce_paper $(REPRODUCE_COGIRO)
	$(BIN)/snakemake reproduce_comparison --cores all --forcerun $(COMPARISON_RULES) $(COMPARISON_THREADS)

# Snakemake's HTML reports of what make reproduce wrote (every figure with its caption, from
# workflow/report/): one per study and one for the comparison, under results/report/ (not tracked).
report: $(STAMP)
	$(BIN)/snakemake reproduce_paper --report results/report/paper.html
	$(BIN)/snakemake reproduce_paper --report results/report/physical.html $(PHYSICAL)
	$(BIN)/snakemake reproduce_comparison --report results/report/comparison.html

# The studies make reproduce runs beside and after the paper and physical studies and before the
# comparison (the calibration studies, the Hangprinter study, the large study, the CoGiRo study), on their own: to rerun them without the
# two long studies (the CoGiRo study needs a complete results/physical).
reproduce-extra: $(STAMP)
	$(BIN)/snakemake --cores all --forceall $(REPRODUCE_CALIBRATION)
	$(BIN)/snakemake --cores all --forceall $(REPRODUCE_LARGE)
	$(BIN)/snakemake --cores all --forceall reproduce_paper $(REPRODUCE_COGIRO)

# After an interruption (Ctrl-C, a killed process, a lost machine): release Snakemake's lock and
# finish only what is missing or incomplete. Targets come before --config (both take lists).
resume: $(STAMP)
	$(BIN)/snakemake --unlock reproduce_paper
	$(BIN)/snakemake --cores all --rerun-incomplete reproduce_paper
	$(BIN)/snakemake --unlock reproduce_paper $(PHYSICAL)
	$(BIN)/snakemake --cores all --rerun-incomplete reproduce_paper $(PHYSICAL)
	$(BIN)/snakemake --cores all --rerun-incomplete reproduce_comparison

# The same DAG on the small CI study (config/studies/quick.yaml), written under results/quick/, in
# physical mode under results/quick_physical/, and their comparison (results/quick_comparison.md).
QUICK_CMP := --config study=config/studies/quick.yaml results=results/quick comparison=config/comparisons/quick.yaml
reproduce-quick: $(STAMP)
	$(BIN)/snakemake --cores all reproduce_paper --config study=config/studies/quick.yaml results=results/quick
	$(BIN)/snakemake --cores all reproduce_paper --config study=config/studies/quick_physical.yaml results=results/quick_physical
	$(BIN)/snakemake reproduce_comparison --cores all $(QUICK_CMP)

# Recompute the quick study (both modes, their comparison) and the quick spatial study from scratch and
# accept their tables and figures as the new regression references and baselines (review the diff!).
# `.venv/bin/python -m tests.update_references --only quick_spatial` recomputes one of them.
update-references: $(STAMP)
	$(BIN)/python -m tests.update_references

# The SLURM executor plugin (extra `cluster` of pyproject.toml) into .venv, for
#   .venv/bin/snakemake --profile workflow/profiles/slurm ...
$(CLUSTER_STAMP): $(STAMP)
	$(BIN)/pip install --quiet -e '.[test,docs,cluster]'
	touch $(CLUSTER_STAMP)

cluster-venv: $(CLUSTER_STAMP)

# The quick study through a throw-away single-node SLURM cluster on this machine with the shipped
# profile, compared byte for byte with a local run. Debian/Ubuntu; root or sudo (installs the slurm
# packages on first use, starts and stops the daemons): tests/slurm/local_slurm.sh.
test-slurm: $(CLUSTER_STAMP)
	tests/slurm/test_slurm.sh

clean-venv:
	rm -rf $(VENV)

# Two commands do everything on a fresh machine with Python 3.11 and pip:
#   make reproduce   -- regenerate the paper's figures, tables and summary under results/
#   make test        -- run the test suite
#   make docs        -- build the documentation site into site/ (mkdocs, --strict)
PYTHON ?= python3.11
VENV   := .venv
BIN    := $(VENV)/bin
STAMP  := $(VENV)/.installed
CLUSTER_STAMP := $(VENV)/.installed-cluster

.PHONY: venv test docs reproduce resume reproduce-quick update-references clean-venv cluster-venv test-slurm

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
	$(BIN)/python -m pytest -q

# The documentation site (docs/, mkdocs.yml): every warning is an error.
docs: $(STAMP)
	$(BIN)/mkdocs build --strict -d site

# Every tracked output is recomputed (--forceall): a fresh clone's tracked results are never reused.
reproduce: $(STAMP)
	$(BIN)/snakemake --cores all --forceall reproduce_paper

# After an interruption (Ctrl-C, a killed process, a lost machine): release Snakemake's lock and
# finish only what is missing or incomplete. Targets come before --config (both take lists).
resume: $(STAMP)
	$(BIN)/snakemake --unlock reproduce_paper
	$(BIN)/snakemake --cores all --rerun-incomplete reproduce_paper

# The same DAG on the small CI study (config/studies/quick.yaml), written under results/quick/.
reproduce-quick: $(STAMP)
	$(BIN)/snakemake --cores all reproduce_paper --config study=config/studies/quick.yaml results=results/quick

# Recompute the quick study from scratch and accept its tables as the new regression references
# (review the diff!).
update-references: $(STAMP)
	$(BIN)/snakemake --cores all --forceall reproduce_paper --config study=config/studies/quick.yaml results=results/quick
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

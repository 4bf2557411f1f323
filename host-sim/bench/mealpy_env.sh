# Sourced by the mealpy benchmarks: makes mealpy available in its own virtual environment,
# target/mealpy-venv (python3 and network access to PyPI on first use), and sets VENV and
# MEALPY_VERSION. Expects ROOT (the repository root).
VENV="$ROOT/target/mealpy-venv"
if [ ! -x "$VENV/bin/python" ]; then
    python3 -m venv "$VENV"
fi
if ! "$VENV/bin/python" -c "import mealpy" 2>/dev/null; then
    "$VENV/bin/pip" install --quiet mealpy
fi
MEALPY_VERSION="$("$VENV/bin/python" -c "import mealpy; print(mealpy.__version__)")"

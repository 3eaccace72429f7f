"""strider.fuzzy.Engine agrees with pyfuzzylite to 1e-9 on pyfuzzylite's own example engines.

The engines strider does not load, and the one where the two differ on purpose (README, "The
fuzzy engine: Agreement with fuzzylite"), are listed with the reason, so that a change in
either shows up here.
"""

import glob
import os
import zlib

import fuzzylite as fl
import numpy as np
import pytest

import strider
from strider.fuzzy import Engine

ROOT = os.path.join(os.path.dirname(fl.__file__), "examples")
EXAMPLES = sorted(os.path.relpath(p, ROOT) for p in glob.glob(os.path.join(ROOT, "**", "*.fll"), recursive=True))

NOT_LOADED = {
    # Nine terms of one name, which pyfuzzylite resolves to the first: refused as ambiguous.
    "takagi_sugeno/matlab/juggler.fll": "two terms named 'out1mf'",
}
# A consequent hedge applies to its own conclusion only in strider ("then y is extremely A and
# z is B" gives z the plain degree); pyfuzzylite carries it on.
DIFFERENT = {"takagi_sugeno/octave/sugeno_tip_calculator.fll"}

INPUTS = 2000


def test_the_examples_are_there():
    assert len(EXAMPLES) >= 50


@pytest.mark.parametrize("name", EXAMPLES)
def test_agrees_with_pyfuzzylite(name):
    text = open(os.path.join(ROOT, name)).read()
    if name in NOT_LOADED:
        with pytest.raises(strider.StriderError, match=NOT_LOADED[name]):
            Engine.from_fll(text, file=name)
        return
    ours = Engine.from_fll(text, file=name)
    theirs = fl.FllImporter().from_string(text)
    rng = np.random.default_rng(zlib.crc32(name.encode()))
    xs = {}
    for v in theirs.input_variables:
        x = rng.uniform(v.minimum, v.maximum, INPUTS)
        x[:2] = v.minimum, v.maximum
        xs[v.name] = x
        v.value = x
    theirs.process()
    got = ours.process({k: xs[k] for k in ours.inputs})
    worst = 0.0
    for v in theirs.output_variables:
        want = np.broadcast_to(np.asarray(v.value, dtype=float), (INPUTS,))
        assert np.array_equal(np.isnan(want), np.isnan(got[v.name])), v.name
        ok = ~np.isnan(want)
        worst = max(worst, float(np.max(np.abs(want[ok] - got[v.name][ok]), initial=0.0)))
    if name in DIFFERENT:
        assert worst > 1e-3
    else:
        assert worst <= 1e-9, f"{name}: outputs differ by {worst}"

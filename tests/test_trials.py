"""The one trial key: depths that went through a CSV are one trial."""

import pandas as pd

from lineload.trials import profiles_by_trial, trial_key, trial_label


def test_a_depth_through_text_and_arithmetic_is_the_same_trial():
    assert trial_key("M1", 0.1 + 0.2) == trial_key("M1", 0.3)
    assert trial_key(7, "1.5") == ("7", 1.5)
    # a micrometre apart is another trial
    assert trial_key("M1", 1.0) != trial_key("M1", 1.001)
    assert trial_key("M1", 1.0) != trial_key("M2", 1.0)


def test_label_names_subject_and_depth():
    assert trial_label("M1", 1.0) == "M1 at 1 mm"
    assert trial_label("H2", 0.25) == "H2 at 0.25 mm"


def test_profiles_by_trial_groups_and_sorts_each_trial():
    averaged = pd.DataFrame(
        {
            "subject": ["M1", "M1", "M2", "M1"],
            "depth_mm": [1.0, 1.0, 1.0, 2.0],
            "distance_mm": [0.5, 0.1, 0.3, 0.2],
        }
    )
    trials = profiles_by_trial(averaged)
    assert list(trials) == [("M1", 1.0), ("M2", 1.0), ("M1", 2.0)]
    assert trials[("M1", 1.0)]["distance_mm"].tolist() == [0.1, 0.5]

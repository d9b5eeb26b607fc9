"""Part names: which read as words, and the numbered labels of the others (issue 11 point 3)."""

from __future__ import annotations

import itertools
import random

import pytest

from h2s_print import names as N
from h2s_print.names import PartName, display_names, readable

# ----------------------------------------------------------------------------- readable

READABLE = [
    "body", "shutter button", "shutter_button", "wheel_1", "wheel 2", "left door", "handle",
    "frame shaft", "drawer_front", "leg 12", "wheel_0", "wheel 100", "left door hinge",
    "frame_shaft_2", "dowel.1",  # the loader's suffix for a second "dowel"
    "part 2", "part",  # "part" is not generic: it reads as a label would
    "facade", "decade",  # all-letter hex look-alikes stay words
    "o-ring", "Knob", "mesh handle",  # one real word is enough
]

UNREADABLE = [
    "",  # no token
    "bearing 1 23 2 16 4 13 10 12 11", "bearing 1 22 4 13 10 12 11",  # many tokens
    "original-12", "mesh_0_3", "Node.004", "part 3 7 9", "Cube.001", "mesh 3", "node",
    "Object.2", "geometry_0",
    "0_part0", "5_part5",  # IKEA (MuJoCo) bodies: two numbered tokens, "part0" mixed
    "5_body", "10_base_body", "2_knob",  # PartNet "<id>_<name>": the number comes first
    "dowel_1_10_6_8_7", "sides_1_5_2_4_3",  # a glTF "dowel#1:10:6:8:7" made safe
    "a3f9", "node12", "polySurface3", "leg a3",  # mixed letters and digits
    "3f9a0c", "1a2b3c4d", "c0ffee12",  # hex ids
    "550e8400-e29b-41d4-a716-446655440000",  # a uuid
    "leg 1234",  # number too long
    "leg 01", "leg 007",  # zero-padded counters
    "12", "a 3", "x",  # no word of two letters
    "wheel 1 front",  # the number is not the last token
    "leg 1 2", "3 leg 4",  # two numbers
    "left front door hinge",  # four tokens
]


@pytest.mark.parametrize("name", READABLE)
def test_readable_names(name):
    assert readable(name), name


@pytest.mark.parametrize("name", UNREADABLE)
def test_unreadable_names(name):
    assert not readable(name), name


def test_thresholds_are_the_rule():
    """Each threshold decides its own boundary case (changing one must flip a case here)."""
    words = ["leg", "front", "left", "upper"]
    assert readable(" ".join(words[:N.ID_LIKE_TOKENS_MAX]))
    assert not readable(" ".join(words[:N.ID_LIKE_TOKENS_MAX + 1]))
    assert readable("leg " + "9" * N.NUMBER_MAX_DIGITS)
    assert not readable("leg " + "9" * (N.NUMBER_MAX_DIGITS + 1))
    assert readable("l" * N.WORD_MIN_LETTERS + " 3")
    assert not readable("l" * (N.WORD_MIN_LETTERS - 1) + " 3")
    for word in N.GENERIC_WORDS:
        assert not readable(f"{word}_4") and readable(f"{word}_handle"), word


def test_tokens_split_on_whitespace_underscore_dash_dot():
    assert N.tokens("a_b-c.d e\tf") == ("a", "b", "c", "d", "e", "f")
    assert N.tokens("__x..y  ") == ("x", "y")


# ----------------------------------------------------------------------------- labels


def test_labels_of_a_mixed_model():
    got = display_names(["wheel_1", "5_body", "handle", "0_part0", "shutter_button"])
    assert list(got) == ["wheel_1", "5_body", "handle", "0_part0", "shutter_button"]
    assert got["wheel_1"] == PartName("wheel_1", "wheel 1", True)
    assert got["handle"] == PartName("handle", "handle", True)
    assert got["shutter_button"] == PartName("shutter_button", "shutter button", True)
    # "5_body" keeps its word; "0_part0" has none and is numbered
    assert got["0_part0"] == PartName("0_part0", "part 1", False)
    assert got["5_body"] == PartName("5_body", "body", False)


def test_words_kept_from_ids_are_numbered_in_natural_order():
    got = display_names(["10_base_body", "1_door", "2_knob", "10_knob", "3_knob",
                         "dowel_1_10_6_8_7", "dowel_1_9_6_8_7", "sides_1_5_2_4_3", "0_part0"])
    labels = {p: v.label for p, v in got.items()}
    assert labels == {"10_base_body": "base body", "1_door": "door", "2_knob": "knob 1",
                      "3_knob": "knob 2", "10_knob": "knob 3", "dowel_1_9_6_8_7": "dowel 1",
                      "dowel_1_10_6_8_7": "dowel 2", "sides_1_5_2_4_3": "sides",
                      "0_part0": "part 1"}
    assert not any(v.readable for v in got.values())
    assert N.base_words("part 3 7 9") is None and N.base_words("mesh_0_3") is None


def test_words_kept_from_ids_never_take_a_readable_name():
    got = display_names(["knob", "2_knob", "3_knob"])
    assert got["knob"].label == "knob"
    assert {got["2_knob"].label, got["3_knob"].label} == {"part 1", "part 2"}


def test_numbering_follows_sorted_names_not_input_order():
    parts = ["mesh_0_3", "Node.004", "original-12", "a3f9", "wheel_1", "part 3 7 9", "body"]
    expected = display_names(sorted(parts))
    assert {p: v.label for p, v in expected.items() if not v.readable} == {
        "Node.004": "part 1", "a3f9": "part 2", "mesh_0_3": "part 3", "original-12": "part 4",
        "part 3 7 9": "part 5"}
    for perm in itertools.permutations(parts):
        got = display_names(list(perm))
        assert list(got) == list(perm)  # keys in input order
        assert got == expected  # same values whatever the order


def test_numbering_is_deterministic_on_a_big_shuffled_model():
    parts = [f"bearing {i} 23 2 16 4 13 10 12 11" for i in range(40)] + ["frame", "lid"]
    want = display_names(parts)
    rng = random.Random(11)
    for _ in range(20):
        shuffled = parts[:]
        rng.shuffle(shuffled)
        assert display_names(shuffled) == want


def test_generated_labels_skip_readable_ones():
    got = display_names(["part 2", "mesh_0_3", "Node.004", "original-12"])
    assert got["part 2"] == PartName("part 2", "part 2", True)
    assert [got[p].label for p in ("Node.004", "mesh_0_3", "original-12")] == [
        "part 1", "part 3", "part 4"]


def test_collisions_are_case_and_underscore_blind():
    got = display_names(["Part_1", "mesh_0_3", "Node.004"])
    assert got["Part_1"].label == "Part 1" and got["Part_1"].readable
    assert [got["Node.004"].label, got["mesh_0_3"].label] == ["part 2", "part 3"]


def test_readable_names_with_one_label_are_both_numbered():
    got = display_names(["wheel_1", "wheel 1", "Wheel_1", "body", "0_part0"])
    assert got["body"].readable
    assert not any(got[p].readable for p in ("wheel_1", "wheel 1", "Wheel_1", "0_part0"))
    assert all(v.label.startswith("part ") for p, v in got.items() if p != "body")
    # shuffled input, same labels
    assert display_names(["0_part0", "Wheel_1", "body", "wheel 1", "wheel_1"]) == got


def test_the_shared_label_is_given_to_no_number():
    got = display_names(["part_1", "part 1", "mesh_0_3"])
    labels = [v.label for v in got.values()]
    assert "part 1" not in labels and len(set(labels)) == 3


@pytest.mark.parametrize("seed", range(30))
def test_labels_are_unique(seed):
    rng = random.Random(seed)
    pool = READABLE + UNREADABLE + [f"part {i}" for i in range(1, 8)] + ["Part_3", "part_5"]
    parts = rng.sample(pool, rng.randint(1, len(pool)))
    got = display_names(parts)
    assert set(got) == set(parts)
    keys = [" ".join(v.label.split()).casefold() for v in got.values()]
    assert len(keys) == len(set(keys)), got
    for p, v in got.items():
        assert v.part == p
        if v.readable:
            assert readable(p) and v.label == p.replace("_", " ")


def test_label_format_from_the_caller():
    got = display_names(["mesh_0_3", "Node.004", "Teil 2"], label_format="Teil {n}")
    assert got["Teil 2"].label == "Teil 2"
    assert [got["Node.004"].label, got["mesh_0_3"].label] == ["Teil 1", "Teil 3"]
    assert display_names(["mesh_0_3"], label_format="({n})")["mesh_0_3"].label == "(1)"


@pytest.mark.parametrize("bad", ["part", "part {m}", "part {0}", "part {n"])
def test_label_format_must_number(bad):
    with pytest.raises(ValueError):
        display_names(["mesh_0_3"], label_format=bad)


def test_repeated_and_empty_inputs():
    assert display_names([]) == {}
    got = display_names(["mesh_0_3", "mesh_0_3", "lid"])
    assert list(got) == ["mesh_0_3", "lid"] and got["mesh_0_3"].label == "part 1"


def test_values_are_frozen():
    value = display_names(["lid"])["lid"]
    with pytest.raises(AttributeError):
        value.label = "x"  # type: ignore[misc]


def test_numbered_labels_follow_the_order_given_then_the_names():
    """Parts called by a number are numbered in the order given (the sequence stage passes
    the start part first, then larger before smaller: "Part 1: the first box", where a
    read-through met "Part 5: the first box"); parts the order leaves out come after, by
    name; readable names keep their own."""
    parts = ["0_part0", "1_part1", "2_part2", "3_part3", "seat"]
    names = display_names(parts, order=["3_part3", "1_part1"])
    assert names["3_part3"].label == "part 1"
    assert names["1_part1"].label == "part 2"
    assert names["0_part0"].label == "part 3"
    assert names["2_part2"].label == "part 4"
    assert names["seat"].label == "seat" and names["seat"].readable
    # without an order: by name, as before
    plain = display_names(parts)
    assert [plain[p].label for p in parts[:4]] == ["part 1", "part 2", "part 3", "part 4"]

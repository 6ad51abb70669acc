"""The carrier bookkeeping both machine pass builders share, and where their policies differ."""

from __future__ import annotations

from illuknit.formats.carriers import (
    KNITERATE_CARRIERS,
    SWG_CARRIERS,
    CarrierBook,
    CarrierPolicy,
    js_key_order,
)
from illuknit.knitout.program import Bed, Direction, Needle


def _book_with(policy: CarrierPolicy = SWG_CARRIERS) -> CarrierBook:
    book = CarrierBook(policy)
    book.bring_in("in", ("2", "10", "1"))
    book.set_last(("1",), Direction.RIGHT, Needle(Bed.FRONT, 4))
    book.set_last(("2",), Direction.LEFT, Needle(Bed.FRONT, 4))
    book.set_last(("10",), Direction.RIGHT, Needle(Bed.BACK, 9))
    return book


def test_kick_order_differs_only_for_negative_slots() -> None:
    kicks = {3: ["1"], -2: ["2"], 0: ["3"], -5: ["4"]}
    assert js_key_order(kicks) == [0, 3, -2, -5]
    assert SWG_CARRIERS.kick_order(kicks) == [0, 3, -2, -5]
    assert KNITERATE_CARRIERS.kick_order(kicks) == [-5, -2, 0, 3]
    positive = {7: ["1"], 2: ["2"]}
    assert SWG_CARRIERS.kick_order(positive) == KNITERATE_CARRIERS.kick_order(positive) == [2, 7]


def test_only_a_machine_with_a_hook_tracks_it() -> None:
    swg, kniterate = CarrierBook(SWG_CARRIERS), CarrierBook(KNITERATE_CARRIERS)
    swg.bring_in("inhook", ("3",))
    kniterate.bring_in("inhook", ("3",))
    assert swg["3"].used_hook and not kniterate["3"].used_hook
    assert swg["3"].pending_in == ("inhook", ("3",))
    assert KNITERATE_CARRIERS.kick_roller == 0 and SWG_CARRIERS.kick_roller is None


def test_carriers_are_visited_in_number_order() -> None:
    assert _book_with().in_order() == ["1", "2", "10"]


def test_yarn_side_of_its_last_needle_decides_the_kick() -> None:
    book = _book_with()
    # at needle 4 itself: "1" went right so hangs right of it, "2" went left so hangs left of
    # it, each parked on its own side already; "10" hangs right, parked right: none moves
    assert list(book.in_the_way(4, (), rack_floor=0)) == []
    # at needle 3 both yarns at 4 hang right of it, and "2" is parked going left: kicked right
    assert list(book.in_the_way(3, (), rack_floor=0)) == [("2", Direction.RIGHT, 4)]
    # a back needle shifts with the racking; the pass's own carriers are never kicked aside
    assert list(book.in_the_way(20, ("1", "2"), rack_floor=2)) == [("10", Direction.LEFT, 11)]


def test_kicks_before_a_pass() -> None:
    book = _book_with()
    # parked going the pass's way: always kicked, at where it is parked
    assert book.kicks_before(("1",), Direction.RIGHT, 8, rack_floor=0) == {4: ["1"]}
    # parked the other way, beyond the pass's slot: kicked back to that slot
    assert book.kicks_before(("2",), Direction.RIGHT, 2, rack_floor=0) == {2: ["2"]}
    assert book.kicks_before(("2",), Direction.RIGHT, 6, rack_floor=0) == {}
    book.park(["2"], 1, Direction.RIGHT)
    assert book["2"].kick == (Needle(Bed.FRONT, 1), Direction.RIGHT)


def test_a_moved_loop_takes_its_yarn_along() -> None:
    book = _book_with()
    book.follow_loop(Needle(Bed.FRONT, 4), Needle(Bed.BACK, 4))
    assert book["1"].last == (Needle(Bed.BACK, 4), Direction.RIGHT)
    assert book["1"].kick == (Needle(Bed.FRONT, 4), Direction.RIGHT)

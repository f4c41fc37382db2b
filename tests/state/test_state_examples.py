"""The state examples reach their result in the lattice world on every shipped car, snakes of 5 to
30 modules and 20 random structures of 20 to 60 modules, with and without 10 % packet loss, from
the module where the program enters (issue 17)."""

from __future__ import annotations

import pytest

from tests.state.state_harness import CONFIGS, RANDOM, hop_distances, run

SNAKES = ("snake5", "snake8", "snake15", "snake22", "snake30")
STRUCTURES = tuple(dict.fromkeys(CONFIGS + SNAKES + RANDOM))
LOSSES = (0.0, 0.1)


@pytest.mark.parametrize("loss", LOSSES)
@pytest.mark.parametrize("config", STRUCTURES)
def test_gradient_is_the_hop_distance(config: str, loss: float) -> None:
    result = run("gradient.rdcd", config, seed=3, loss=loss)
    assert result.values("hops") == hop_distances(result.structure)
    assert result.errors() == {}


@pytest.mark.parametrize("loss", LOSSES)
@pytest.mark.parametrize("config", STRUCTURES)
def test_the_entry_module_counts_the_modules(config: str, loss: float) -> None:
    result = run("count.rdcd", config, seed=5, loss=loss)
    assert result.value(result.structure.entry, "size") == len(result.structure.modules)
    assert result.errors() == {}


@pytest.mark.parametrize("loss", LOSSES)
@pytest.mark.parametrize("config", STRUCTURES)
def test_the_lowest_modules_are_bottom(config: str, loss: float) -> None:
    result = run("lowest.rdcd", config, seed=7, loss=loss)
    heights = {m: spec.position[2] for m, spec in result.structure.modules.items()}
    lowest = min(heights.values())
    assert result.roles() == {m: "Bottom" if z == lowest else "Upper" for m, z in heights.items()}
    assert set(result.values("lowest").values()) == {lowest}
    assert result.errors() == {}


def test_the_gradient_follows_a_cut() -> None:
    """Cut a snake in two: the part cut off forgets the lost neighbour's value and climbs to 127
    (none of its modules can reach the entry any more); the rest keeps its distances."""
    result = run("gradient.rdcd", "snake8")
    world, shape = result.world, result.structure
    distances = hop_distances(shape)
    assert result.values("hops") == distances
    near = next(m for m, d in distances.items() if d == 3)
    far = next(m for m, d in distances.items()
               if d == 4 and near in {o for o, _ in shape.neighbours(m).values()})
    for module, other in ((near, far), (far, near)):
        hal = world.runtimes[module].hal
        lost = {ch for ch, (neighbour, _) in shape.neighbours(module).items() if neighbour == other}
        hal._connected = hal._connected - lost  # type: ignore[attr-defined]
    world.advance(30.0)
    values = result.values("hops")
    assert all(values[m] == 127 for m, d in distances.items() if d >= 4), values
    assert all(values[m] == d for m, d in distances.items() if d <= 3), values


@pytest.mark.parametrize("loss", LOSSES)
@pytest.mark.parametrize("config", STRUCTURES)
def test_the_travelling_hop_count_grows_by_one_per_module(config: str, loss: float) -> None:
    """Every module's hop is one more than that of the neighbour that first brought it the program
    (its parent in the tree), so it is the length of the path the program first took: the hop
    distance without loss, at least that with loss."""
    result = run("hops.rdcd", config, seed=11, loss=loss)
    shape, hops = result.structure, result.values("hop")
    distances = hop_distances(shape)
    assert hops[shape.entry] == 0
    for module, runtime in result.world.runtimes.items():
        if module == shape.entry:
            continue
        parent, _ = shape.neighbours(module)[runtime.parent_channel]
        assert hops[module] == hops[parent] + 1, (module, parent)
        assert hops[module] >= distances[module]
    if loss == 0.0:
        assert hops == distances
    assert result.errors() == {}

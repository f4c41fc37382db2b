"""The order of the semantic passes."""

from __future__ import annotations

from operator import attrgetter

from rdcd_core.semantics import actions, conflicts, deployment, limits, members, states
from rdcd_core.semantics.bodies import check_bodies
from rdcd_core.semantics.constants import fold_constants
from rdcd_core.semantics.context import Context
from rdcd_core.semantics.hierarchy import build_roles
from rdcd_core.semantics.inlining import check_inlined_scoping
from rdcd_core.semantics.model import Model
from rdcd_core.semantics.recursion import check_recursion
from rdcd_core.sequences.check import check_names
from rdcd_core.sequences.lower import with_progress_states
from rdcd_core.syntax import ast


def run(program: ast.Program) -> Model:
    program = with_progress_states(program)  # a sequence's progress is a module state
    model = Model(program, {}, [], [])
    ctx = Context(model)
    build_roles(ctx, program)
    states.declare_module_states(ctx)
    members.copy_down(ctx)
    fold_constants(ctx)
    states.fold_initials(ctx)
    states.check_parameters(ctx)
    states.check_shadowing(ctx)
    members.check_missing_definitions(ctx)
    children = members.children_map(ctx)
    check_bodies(ctx, children)
    actions.check_positions(ctx, program)
    states.layout(ctx)
    check_recursion(ctx)
    check_inlined_scoping(ctx)
    seen = deployment.check_deployment(ctx)
    limits.check_limits(ctx, seen)
    deployment.check_discovery_order(ctx, seen)
    conflicts.check_conflicts(ctx, seen)
    deployment.check_dead_roles(ctx)
    model.diagnostics += check_names(model)
    model.diagnostics.sort(key=lambda d: (d.span.start, d.span.end, d.code))
    model.references.sort(key=attrgetter("name.span.start"))
    return model

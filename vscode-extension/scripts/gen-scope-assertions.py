# Regenerates test/grammar/assert/scopes.rdcd (vscode-tmgrammar-test assertions) from the table below.
# generates test/grammar/assert/scopes.rdcd: source lines each followed by assertion lines
src = []
def L(line, *asserts):
    src.append((line, asserts))
L('abstract role Wheel extends Module {', ('abstract','storage.modifier.abstract.rdcd'), ('role','storage.type.role.rdcd'), ('Wheel','entity.name.type.role.rdcd'), ('extends','storage.modifier.extends.rdcd'), ('Module','entity.other.inherited-class.role.rdcd'), ('{','punctuation.section.block.begin.bracket.curly.rdcd'))
L('  abstract constant a, b;', ('abstract','storage.modifier.abstract.rdcd'), ('constant','storage.type.constant.rdcd'), ('a','variable.other.constant.declaration.rdcd'), (',','punctuation.separator.comma.rdcd'), ('b','variable.other.constant.declaration.rdcd'), (';','punctuation.terminator.statement.rdcd'))
L('  constant c := -12;', ('c','variable.other.constant.declaration.rdcd'), (':=','keyword.operator.assignment.rdcd'), ('-','keyword.operator.arithmetic.rdcd'), ('12','constant.numeric.integer.decimal.rdcd'))
L('  self.center_position == EAST_WEST && !(self.y > 0) || a != UP;', ('self','variable.language.self.rdcd'), ('.','punctuation.accessor.rdcd'), ('center_position','support.function.builtin.rdcd'), ('==','keyword.operator.comparison.rdcd'), ('EAST_WEST','constant.language.axis.rdcd'), ('&&','keyword.operator.logical.rdcd'), ('!','keyword.operator.logical.rdcd'), ('y','support.function.builtin.rdcd'), ('0','constant.numeric.integer.decimal.rdcd'), ('||','keyword.operator.logical.rdcd'), (' a ','variable.other.constant.rdcd'), ('!=','keyword.operator.comparison.rdcd'), ('UP','constant.language.direction.rdcd'))
L('  sizeof(connected_role(DOWN, Reverse)) >= 1; /* block */', ('sizeof','support.function.builtin.rdcd'), ('connected_role','support.function.builtin.rdcd'), ('DOWN','constant.language.direction.rdcd'), ('Reverse','entity.name.type.role.rdcd'), ('>=','keyword.operator.comparison.rdcd'), ('/* block */','comment.block.rdcd'))
L('  self.x() < self.z() + 1 - self.total_connected();', ('x','support.function.builtin.rdcd'), ('<','keyword.operator.comparison.rdcd'), ('z','support.function.builtin.rdcd'), ('+','keyword.operator.arithmetic.rdcd'), ('total_connected','support.function.builtin.rdcd'))
L('  startup move() {', ('startup','storage.modifier.method-kind.rdcd'), ('move','entity.name.function.method.rdcd'), ('(','punctuation.section.parens.begin.bracket.round.rdcd'), (')','punctuation.section.parens.end.bracket.round.rdcd'))
L('    if (self.y() > 0) self.handleEvent(EVENT_PROXIMITY_5, { Wheel.stop(); });', ('if','keyword.control.conditional.rdcd'), ('handleEvent','support.function.builtin.rdcd'), ('EVENT_PROXIMITY_5','constant.language.event.rdcd'), ('Wheel','entity.name.type.role.rdcd'), ('stop','entity.name.function.command.rdcd'))
L('    else self.helper();', ('else','keyword.control.conditional.rdcd'), ('helper','entity.name.function.method.rdcd'))
L('  }')
L('  command stop() {', ('command','storage.modifier.method-kind.rdcd'), ('stop','entity.name.function.method.rdcd'))
L('    self.assumeRole(Reverse, { self.turnContinuously(-1); });', ('assumeRole','support.function.builtin.rdcd'), ('Reverse','entity.name.type.role.mixin.rdcd'), ('turnContinuously','support.function.builtin.rdcd'))
L('  }')
L('  behavior steer() { }', ('behavior','storage.modifier.method-kind.rdcd'), ('steer','entity.name.function.method.rdcd'))
L('  abstract helper();', ('abstract','storage.modifier.abstract.rdcd'), ('helper','entity.name.function.method.rdcd'))
L('  plain() { }', ('plain','entity.name.function.method.rdcd'))
L('}', ('}','punctuation.section.block.end.bracket.curly.rdcd'))
L('role Reverse modifies Wheel { }', ('Reverse','entity.name.type.role.mixin.rdcd'), ('modifies','storage.modifier.modifies.rdcd'), ('Wheel','entity.other.inherited-class.role.rdcd'))
L('role Other', ('Other','entity.name.type.role.rdcd'))
L('  extends Wheel { }', ('extends','storage.modifier.extends.rdcd'), ('Wheel','entity.other.inherited-class.role.rdcd'))
L('deployment { RightWheel, Axle } // end', ('deployment','keyword.other.deployment.rdcd'), ('RightWheel','entity.name.type.role.rdcd'), (',','punctuation.separator.comma.rdcd'), ('Axle','entity.name.type.role.rdcd'), ('// end','comment.line.double-slash.rdcd'))
out = ['// SYNTAX TEST "source.rdcd" "token classes of RDCD "']
for line, asserts in src:
    out.append(line)
    for a in asserts:
        tok, scope = a[0], a[1]
        nth = a[2] if len(a) > 2 else 0
        import re
        pat = re.escape(tok)
        if re.fullmatch(r'\w+', tok):
            pat = r'(?<!\w)' + pat + r'(?!\w)'
        start = [m.start() for m in re.finditer(pat, line)][nth]
        if tok.startswith(' ') and tok.endswith(' '):
            start += 1; tok = tok.strip()
        if start < 2:
            out.append('// ' + '<' + '-' * (len(tok) - 1 + start) + ' ' + scope) if start == 0 else None
            if start == 1: raise SystemExit('col 1 unsupported')
        else:
            out.append('//' + ' ' * (start - 2) + '^' * len(tok) + ' ' + scope)
open(__import__('os').path.join(__import__('os').path.dirname(__file__), '..', 'test', 'grammar', 'assert', 'scopes.rdcd'), 'w').write('\n'.join(out) + '\n')

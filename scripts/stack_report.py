#!/usr/bin/env python3
"""Worst-case stack of the core's public entry points, from GCC's -fcallgraph-info=su files.

usage: stack_report.py [--limit BYTES] [--top N] [--fail] [--src ROOT] [--no-tables] FILE.ci...

Each function's own frame comes from its "N bytes (static)" label; the worst case of a
function is its frame plus the worst of the functions it calls, over the whole call graph.
Library functions (memcpy, snprintf, ...) count 0 (the image's libc is nano newlib); a
recursive cycle is reported and counted once round.

Calls through function pointers: GCC marks each one as an edge to "__indirect_call" labelled
with the call's source position. The C sources named in the .ci files (read from ROOT, the
current directory by default) are scanned for where the core's own functions are put into
function pointers: a table's initializer (`.on_run = loiter_run`, or `{"add", alg_add, false}`
by position), an assignment to a member (`tr->publish = lb_publish`), an argument
(`each_item(list, add_plain, x)`), a local variable. Those flows are followed (a parameter
that is stored into a member or passed on carries what its callers pass), and an indirect
call `b->ops->on_run(...)` reaches every core function that can sit in that slot of that
struct type (kelp_bhv_ops.on_run; by slot name alone where the type cannot be told), a call
through a parameter `fn(...)` every function the callers pass there. A call whose slot or
parameter only ever holds what the library's caller supplies (kelp_field_sink's publish/warn,
log callbacks, the transport, crypto, the acomms codec view the edge fills) is not followed:
the report lists those sites by slot. --no-tables follows direct calls only.

Prints the entry points (kelp_* functions with external linkage) over the limit and the
largest ones, each with its deepest chain; a hop through a function pointer is marked
`=[slot]=>`.
"""
import os
import re
import sys

NODE = re.compile(r'node: \{ title: "([^"]+)" label: "([^"]*)"')
EDGE = re.compile(r'edge: \{ sourcename: "([^"]+)" targetname: "([^"]+)"(?: label: "([^"]*)")?')
SIZE = re.compile(r'\\n(\d+) bytes \((static|dynamic|dynamic,bounded)\)')
LOC = re.compile(r'^[^\\]*\\n([^:\\]+):(\d+):(\d+)')
INDIRECT = '__indirect_call'
IDENT = re.compile(r'[A-Za-z_]\w*')
KEYWORDS = {'return', 'case', 'sizeof', 'goto', 'else', 'do', 'if', 'while', 'for', 'switch',
            'const', 'volatile', 'static', 'struct', 'union', 'enum', 'extern', 'inline',
            'unsigned', 'signed', 'typedef', 'register', 'restrict', '_Alignof', 'default'}
QUALIFIERS = {'const', 'volatile', 'static', 'struct', 'union', 'enum', 'extern', 'inline',
              'register', 'restrict'}


# ----------------------------------------------------------------------------- C text helpers

def strip_c(text):
    """Comments, string and character literals and preprocessor lines blanked with spaces, so
    offsets, lines and columns stay those of the file."""
    out, i, n = list(text), 0, len(text)

    def blank(a, b):
        for k in range(a, b):
            if out[k] != '\n':
                out[k] = ' '
    bol = True
    while i < n:
        c = text[i]
        if bol and c == '#':
            j = i
            while j < n and text[j] != '\n':
                j += 2 if text[j] == '\\' else 1
            blank(i, min(j, n)); i = j; continue
        if c == '\n':
            bol = True; i += 1; continue
        if not c.isspace():
            bol = False
        if text.startswith('/*', i):
            j = text.find('*/', i + 2); j = n if j < 0 else j + 2
            blank(i, j); i = j; continue
        if text.startswith('//', i):
            j = text.find('\n', i); j = n if j < 0 else j
            blank(i, j); i = j; continue
        if c in '"\'':
            j = i + 1
            while j < n and text[j] != c and text[j] != '\n':
                j += 2 if text[j] == '\\' else 1
            blank(i + 1, min(j, n)); i = j + 1; continue
        i += 1
    return ''.join(out)


def match_close(t, i):
    """Index of the bracket closing the one at t[i]."""
    pairs = {'{': '}', '(': ')', '[': ']'}
    stack = [pairs[t[i]]]
    j = i + 1
    while j < len(t) and stack:
        c = t[j]
        if c in pairs:
            stack.append(pairs[c])
        elif c in ')}]':
            stack.pop()
        j += 1
    return j - 1


def split_top(s, sep=','):
    """s split at sep outside brackets, with each part's offset."""
    parts, depth, start = [], 0, 0
    for k, c in enumerate(s):
        if c in '([{':
            depth += 1
        elif c in ')]}':
            depth -= 1
        elif c == sep and depth == 0:
            parts.append((s[start:k], start)); start = k + 1
    parts.append((s[start:], start))
    return parts


def decl_name_type(decl):
    """(name, type) of one declaration `const kelp_bhv *b`, `void (*post)(...)`, `char buf[8]`."""
    m = re.search(r'\(\s*\*\s*(?:const\s+)?(\w+)\s*\)\s*\(', decl)
    if m:
        return m.group(1), '<fnptr>'
    d = re.sub(r'\[[^\]]*\]', ' ', decl).split('=')[0]
    words = [w for w in IDENT.findall(d) if w not in QUALIFIERS]
    if not words:
        return None, None
    return words[-1], (words[-2] if len(words) > 1 else None)


# ----------------------------------------------------------------------------- the C model

class Func:
    def __init__(self, path, name, start, end, params, static):
        self.path, self.name, self.start, self.end = path, name, start, end
        self.params, self.static = params, static      # params: [(name, type)]
        self.locals = {}                                # name -> type, filled lazily
        self.key = (path, name)


class Model:
    """Structs, functions, and where functions flow into function pointers."""

    def __init__(self, root, paths, headers):
        self.root = root
        self.text, self.funcs, self.file_funcs = {}, {}, {}
        self.structs, self.alias = {}, {}
        self.externs = {}                               # name -> Func (external linkage)
        self.flows = {}                                 # dest node -> set of source nodes
        self._decl_cache = {}
        for h in headers:
            self._structs(strip_c(self._read(h)), h)
        for p in paths:
            t = strip_c(self._read(p))
            self.text[p] = t
            self._structs(t, p)
            self._functions(p, t)
        for p in paths:
            self._flows(p)

    def _read(self, p):
        with open(os.path.join(self.root, p), encoding='utf-8', errors='replace') as fh:
            return fh.read()

    # -- types
    def canon(self, t):
        seen = set()
        while t in self.alias and t not in seen:
            seen.add(t); t = self.alias[t]
        return t

    def _structs(self, t, where):
        for m in re.finditer(r'typedef\s+(?:struct|union)\s+(\w+)\s+(\w+)\s*;', t):
            self.alias[m.group(2)] = m.group(1)
        for m in re.finditer(r'typedef\s+(?:const\s+)?(\w+)\s+(\w+)\s*;', t):
            if m.group(1) not in ('struct', 'union', 'enum'):
                self.alias[m.group(2)] = m.group(1)
        for m in re.finditer(r'(typedef\s+)?\b(struct|union)\s+(\w+)?\s*\{', t):
            o = m.end() - 1
            c = match_close(t, o)
            tail = re.match(r'\s*(\w+)\s*;', t[c + 1:])
            tag = m.group(3)
            if m.group(1) and tail:
                name = tail.group(1)
                if tag:
                    self.alias[tag] = name
            elif tag:
                name = tag
            else:
                continue                                # anonymous: typed where it is declared
            self.structs[name] = self._fields(t[o + 1:c], f'{where}:{name}')

    def _fields(self, body, anon_prefix):
        """[(field, type)] of a struct body; a nested struct/union gets its own anonymous type."""
        fields = []
        k = 0
        parts = split_top(body, ';')
        for part, off in parts:
            part = part.strip()
            if not part:
                continue
            m = re.match(r'(?:struct|union)\s*(\w+)?\s*\{', part)
            if m:
                o = part.index('{')
                c = match_close(part, o)
                k += 1
                anon = f'{anon_prefix}#{k}'
                self.structs[anon] = self._fields(part[o + 1:c], anon)
                rest = part[c + 1:]
                for d, _ in split_top(rest):
                    nm = IDENT.findall(d)
                    if nm:
                        fields.append((nm[0], anon))
                    else:                               # an anonymous member: its fields are ours
                        fields.extend(self.structs[anon])
                continue
            decls = split_top(part)
            name, typ = decl_name_type(decls[0][0])
            if name:
                fields.append((name, typ))
            for d, _ in decls[1:]:
                nm, _ = decl_name_type('x ' + d)
                if nm:
                    fields.append((nm, typ))
        return fields

    def field_type(self, typ, field):
        if typ is None:
            return None
        for f, ft in self.structs.get(self.canon(typ), []):
            if f == field:
                return self.canon(ft) if ft else None
        return None

    # -- functions
    def _functions(self, p, t):
        i, depth, last = 0, 0, 0
        funcs = []
        n = len(t)
        while i < n:
            c = t[i]
            if c == '{':
                head = t[last:i]
                end = match_close(t, i)
                m = re.search(r'(\w+)\s*\(([^{};]*)\)\s*$', head)
                if m and '=' not in head and not re.match(r'\s*(?:typedef|struct|union|enum)\b',
                                                          head) and m.group(1) not in KEYWORDS:
                    params = []
                    ptxt = m.group(2)
                    if ptxt.strip() not in ('', 'void'):
                        for d, _ in split_top(ptxt):
                            params.append(decl_name_type(d))
                    f = Func(p, m.group(1), i, end, params, bool(re.search(r'\bstatic\b', head)))
                    funcs.append(f)
                    self.funcs[f.key] = f
                    if not f.static:
                        self.externs[f.name] = f
                i = end + 1
                last = i
                continue
            if c == ';':
                last = i + 1
            i += 1
        self.file_funcs[p] = funcs

    def enclosing(self, p, off):
        for f in self.file_funcs.get(p, []):
            if f.start <= off <= f.end:
                return f
        return None

    def visible_func(self, p, name):
        f = self.funcs.get((p, name))
        if f:
            return f
        return self.externs.get(name)

    def local_type(self, fn, name, before=None):
        """Declared type of `name` in fn (a parameter or a local)."""
        if not fn:
            return None
        for pn, pt in fn.params:
            if pn == name:
                return self.canon(pt) if pt else None
        return self.decl_in(fn.path, fn.start, fn.end, name)

    def decl_in(self, p, start, end, name):
        """Type of the last declaration of `name` in text[start:end] (None: not declared)."""
        key = (p, start, end, name)
        if key in self._decl_cache:
            return self._decl_cache[key]
        t = self.text[p]
        found = None
        pat = re.compile(r'(\b\w+|\})\s*(?:\*\s*|const\s+)*\b' + re.escape(name) +
                         r'\s*(?:\[[^\]]*\]\s*)*[=;,)]')
        if t.find(name, start, end) >= 0:
            for m in pat.finditer(t, start, end):
                w = m.group(1)
                if w == '}':
                    found = self.anon_at(p, self.open_of(t, m.start(1))) or found
                elif w not in KEYWORDS and not w.isdigit():
                    found = self.canon(w)
        self._decl_cache[key] = found
        return found

    @staticmethod
    def open_of(t, j):
        depth = 0
        while j >= 0:
            if t[j] == '}':
                depth += 1
            elif t[j] == '{':
                depth -= 1
                if depth == 0:
                    return j
            j -= 1
        return 0

    def anon_at(self, p, o):
        key = f'<anon@{p}:{o}>'
        if key not in self.structs:
            t = self.text[p]
            self.structs[key] = self._fields(t[o + 1:match_close(t, o)], key)
        return key

    def expr_type(self, fn, chain, off):
        """Type of a postfix chain [(sep, ident)] (sep '' for the first)."""
        typ = None
        for k, (sep, ident) in enumerate(chain):
            if k == 0:
                typ = self.local_type(fn, ident, off)
                if typ is None:
                    typ = self.file_object_type(fn.path if fn else None, ident)
            else:
                typ = self.field_type(typ, ident)
            if typ is None:
                return None
        return typ

    def file_object_type(self, p, name):
        return self.decl_in(p, 0, len(self.text[p]), name) if p else None

    # -- flows: nodes are ('fn', path, name) | ('param', path, func, k) | ('slot', type, field)
    #    | ('var', path, func, name)
    def add_flow(self, dest, src, kind='callback'):
        """src flows into dest; a function put there directly is tagged with how: 'table' (an
        initializer of static storage: a const table) or 'callback' (an argument, an assignment,
        an automatic struct: the core passing its own function as a callback)."""
        if dest and src:
            if src[0] == 'fn':
                src = src[:3] + (kind,)
            self.flows.setdefault(dest, set()).add(src)

    def value_node(self, p, fn, expr, off):
        """The node a value expression reads: a function, a parameter, a local, a member."""
        e = expr.strip()
        e = re.sub(r'^\(\s*\w+\s*\)\s*', '', e)        # a cast to a typedef'd pointer type
        e = e.lstrip('&').strip()
        chain = parse_chain(e)
        if not chain or len(''.join(s + i for s, i in chain)) < len(re.sub(r'\[[^\]]*\]|\s', '', e)):
            return None
        if len(chain) == 1:
            return self.name_node(p, fn, chain[0][1])
        typ = self.expr_type(fn, chain[:-1], off)
        return ('slot', typ, chain[-1][1])

    def name_node(self, p, fn, name):
        if fn:
            for k, (pn, _) in enumerate(fn.params):
                if pn == name:
                    return ('param', fn.path, fn.name, k)
            if self.decl_in(p, fn.start, fn.end, name):
                return ('var', fn.path, fn.name, name)
        f = self.visible_func(p, name)
        if f:
            return ('fn', f.path, f.name)
        return None

    def _flows(self, p):
        t = self.text[p]
        # initializers: TYPE name[...] = { ... }  (file scope or in a function)
        for m in re.finditer(r'=\s*\{', t):
            o = m.end() - 1
            c = match_close(t, o)
            fn = self.enclosing(p, m.start())
            typ, is_array = self._init_type(p, t, m.start(), fn)
            if typ is None:
                continue
            head = m.start()
            if typ.startswith('<anon@'):                # `static const struct { ... } T[] =`
                head = int(typ.rsplit(':', 1)[1].rstrip('>'))
            decl = t[max(t.rfind(';', 0, head), t.rfind('{', 0, head), t.rfind('}', 0, head)) + 1:head]
            kind = 'table' if fn is None or re.search(r'\bstatic\b', decl) else 'callback'
            self._init(p, fn, t, o, c, typ, is_array, kind)
        # assignments: X->slot = value; local = value;
        for m in re.finditer(r'([A-Za-z_][\w\.\->\[\]\s]*?)\s*(?<![=!<>+\-*/%&|^])=(?!=)\s*([^;,(){}=]+?)\s*[;,)]', t):
            fn = self.enclosing(p, m.start())
            if not fn:
                continue
            lhs = parse_chain(re.sub(r'\s+', '', m.group(1)).split(',')[-1])
            if not lhs:
                continue
            src = self.value_node(p, fn, m.group(2), m.start())
            if not src or src[0] == 'var' and src[3] == lhs[-1][1]:
                continue
            if len(lhs) == 1:
                dest = self.name_node(p, fn, lhs[0][1])
                if dest and dest[0] == 'fn':
                    continue
            else:
                dest = ('slot', self.expr_type(fn, lhs[:-1], m.start()), lhs[-1][1])
            self.add_flow(dest, src)
        # arguments: G(a, fn, b)
        for m in re.finditer(r'\b([A-Za-z_]\w*)\s*\(', t):
            g = m.group(1)
            if g in KEYWORDS:
                continue
            fn = self.enclosing(p, m.start())
            if not fn or m.start() == fn.start:
                continue
            callee = self.visible_func(p, g)
            if not callee or (callee.path == p and callee.start <= m.start() <= callee.end and
                              t[m.end():callee.start].strip() == ''):
                continue
            if callee.start == m.start() or (callee.path == p and m.start() < callee.start and
                                             t.find('{', m.end()) == callee.start):
                continue                                # the definition itself
            o = m.end() - 1
            c = match_close(t, o)
            for k, (a, aoff) in enumerate(split_top(t[o + 1:c])):
                src = self.value_node(p, fn, a, o + 1 + aoff)
                if src and src[0] in ('fn', 'param', 'var', 'slot'):
                    if src[0] == 'slot' and self.field_type(src[1], src[2]) not in (None, '<fnptr>') \
                            and not self._is_fnptr_alias(self.field_type(src[1], src[2])):
                        continue
                    self.add_flow(('param', callee.path, callee.name, k), src)

    def _is_fnptr_alias(self, typ):
        return typ is not None and typ.endswith('_fn') or typ in ('kelp_helm_sink',)

    def _init_type(self, p, t, eq, fn):
        """(type, is_array) of the object initialized by the `= {` at eq."""
        k = eq - 1
        while k >= 0 and t[k].isspace():
            k -= 1
        is_array = False
        if t[k] == ']':
            is_array = True
            k = t.rfind('[', 0, k)
            k -= 1
            while k >= 0 and t[k].isspace():
                k -= 1
        m = re.search(r'(\w+)$', t[:k + 1])
        if not m:
            return None, False
        j = m.start() - 1
        while j >= 0 and (t[j].isspace() or t[j] == '*'):
            j -= 1
        if t[j] == '}':
            return self.anon_at(p, self.open_of(t, j)), is_array
        m2 = re.search(r'(\w+)$', t[:j + 1])
        if not m2 or m2.group(1) in KEYWORDS:
            return None, False
        return self.canon(m2.group(1)), is_array

    def _init(self, p, fn, t, o, c, typ, is_array, kind):
        body = t[o + 1:c]
        if is_array:
            for part, off in split_top(body):
                s = part.lstrip()
                if s.startswith('{'):
                    po = o + 1 + off + (len(part) - len(s))
                    self._init(p, fn, t, po, match_close(t, po), typ, False, kind)
                else:                                   # an array of function pointers
                    src = self.value_node(p, fn, part, o + 1 + off)
                    if src and src[0] == 'fn':
                        self.add_flow(('slot', typ, '[]'), src, kind)
            return
        fields = self.structs.get(typ, [])
        pos = 0
        for part, off in split_top(body):
            s = part.strip()
            if not s:
                continue
            m = re.match(r'\.(\w+)\s*=\s*', s)
            if m:
                field = m.group(1)
                s = s[m.end():]
                pos = next((k for k, (f, _) in enumerate(fields) if f == field), pos)
            else:
                field = fields[pos][0] if pos < len(fields) else None
            pos += 1
            if field is None:
                continue
            if s.startswith('{'):
                so = t.find('{', o + 1 + off)
                ft = self.field_type(typ, field)
                if ft:
                    self._init(p, fn, t, so, match_close(t, so), ft, False, kind)
                continue
            src = self.value_node(p, fn, s, o + 1 + off)
            if src and src[0] in ('fn', 'param', 'var'):
                self.add_flow(('slot', typ, field), src, kind)

    # -- solving
    def solve(self, kinds):
        """Functions (put there as one of kinds) that can reach each node."""
        memo = {}
        by_field = {}
        for d in self.flows:
            if d[0] == 'slot':
                by_field.setdefault(d[2], set()).add(d)

        def sources(node):
            if node[0] == 'slot':
                typ, field = node[1], node[2]
                if typ is None:
                    return set().union(*[self.flows.get(d, set()) for d in by_field.get(field, ())])
                return self.flows.get(node, set()) | self.flows.get(('slot', None, field), set())
            return self.flows.get(node, set())

        def reach(node, seen):
            if node in memo:
                return memo[node]
            if node in seen:
                return set()
            seen.add(node)
            out = set()
            if node[0] == 'fn':
                if len(node) < 4 or node[3] in kinds:
                    out.add((node[1], node[2]))
            else:
                for s in sources(node):
                    out |= reach(s, seen)
            seen.discard(node)
            if not seen:
                memo[node] = out
            return out
        return lambda node: reach(node, set())


def parse_chain(e):
    """`h->bhv[i].ops->on_run` -> [('', 'h'), ('->', 'bhv'), ('.', 'ops'), ('->', 'on_run')]."""
    e = re.sub(r'\s+', '', e)
    e = re.sub(r'\[[^\[\]]*\]', '', e)
    e = re.sub(r'\[[^\[\]]*\]', '', e)
    m = re.fullmatch(r'([A-Za-z_]\w*)((?:(?:->|\.)[A-Za-z_]\w*)*)', e)
    if not m:
        return None
    chain = [('', m.group(1))]
    for sm in re.finditer(r'(->|\.)([A-Za-z_]\w*)', m.group(2)):
        chain.append((sm.group(1), sm.group(2)))
    return chain


def slot_name(node):
    if node is None:
        return '?'
    if node[0] == 'slot':
        typ = node[1] or '?'
        if typ.startswith('<anon') or ':' in typ:
            typ = '(struct)'
        return f'{typ}.{node[2]}'
    if node[0] == 'param':
        return f'{node[2]}() parameter {node[3] + 1}'
    if node[0] == 'var':
        return f'{node[2]}(): {node[3]}'
    return node[2]


# ----------------------------------------------------------------------------- the report

def base_name(title):
    return title.split(':')[-1].split('.')[0]


def indirect_edges(frame, sites, root, kinds):
    """(callee edges added, not-followed summary): sites are [(caller title, path, line, col)]."""
    paths = sorted({s[1] for s in sites} | {p for p in frame_paths(frame)})
    paths = [p for p in paths if os.path.isfile(os.path.join(root, p))]
    headers = []
    for d in ('include/kelp',):
        full = os.path.join(root, d)
        if os.path.isdir(full):
            headers += sorted(os.path.join(d, f) for f in os.listdir(full) if f.endswith('.h'))
    for p in paths:
        dd = os.path.dirname(p)
        full = os.path.join(root, dd)
        if os.path.isdir(full):
            headers += sorted(os.path.join(dd, f) for f in os.listdir(full) if f.endswith('.h'))
    model = Model(root, paths, sorted(set(headers)))
    reach = model.solve(kinds)
    reach_all = model.solve({'table', 'callback'})
    titles = {}
    for t, (path, _) in frame.items():
        titles.setdefault((path, base_name(t)), []).append(t)
    added, skipped = [], {}
    for caller, path, line, col in sites:
        t = model.text.get(path)
        if t is None:
            skipped.setdefault('(source not found)', []).append(caller)
            continue
        lines = t.split('\n')
        off = sum(len(x) + 1 for x in lines[:line - 1]) + col - 1
        fn = model.enclosing(path, off)
        node, label = None, None
        # the call's callee: the first call expression at the position that is not a function
        # name (GCC puts `f(a, b->op(x))`'s indirect call at f; a macro's at the macro)
        for m in re.finditer(r'([A-Za-z_](?:[\w\.\[\]]|->)*)\s*\(', t[off:off + 400]):
            chain = parse_chain(m.group(1))
            if not chain:
                continue
            if len(chain) == 1:
                cand = model.name_node(path, fn, chain[0][1])
            else:
                cand = ('slot', model.expr_type(fn, chain[:-1], off), chain[-1][1])
            if label is None:
                label = m.group(1)
            if cand and cand[0] != 'fn':
                node = cand
                break
        targets = reach(node) if node else set()
        hit = False
        for fp, fname in sorted(targets):
            for tt in titles.get((fp, fname), []):
                added.append((caller, tt, slot_name(node)))
                hit = True
        if not hit:
            own = node is not None and any(titles.get(x) for x in reach_all(node))
            skipped.setdefault(('core callback: ' if own else '') + slot_name(node) if node else f'{label} (unresolved)', []).append(caller)
    return added, skipped, model


def frame_paths(frame):
    return {p for (p, _) in frame.values() if p}


def main(argv):
    limit, top, files, fail, root, tables, kinds = 1024, 12, [], False, '.', True, {'table'}
    i = 0
    while i < len(argv):
        if argv[i] == '--limit':
            limit = int(argv[i + 1]); i += 2
        elif argv[i] == '--top':
            top = int(argv[i + 1]); i += 2
        elif argv[i] == '--fail':
            fail = True; i += 1
        elif argv[i] == '--src':
            root = argv[i + 1]; i += 2
        elif argv[i] == '--no-tables':
            tables = False; i += 1
        elif argv[i] == '--callbacks':
            kinds = {'table', 'callback'}; i += 1
        else:
            files.append(argv[i]); i += 1
    frame, kind, calls, where, sites = {}, {}, {}, {}, []
    for f in files:
        with open(f, encoding='utf-8', errors='replace') as fh:
            for line in fh:
                m = NODE.search(line)
                if m:
                    title, label = m.group(1), m.group(2)
                    s = SIZE.search(label)
                    if s:
                        lm = LOC.search(label)
                        frame[title] = int(s.group(1))
                        where[title] = (lm.group(1) if lm else None, None)
                        kind[title] = s.group(2)
                    continue
                m = EDGE.search(line)
                if m:
                    if m.group(2) == INDIRECT:
                        lm = re.match(r'(.+):(\d+):(\d+)$', m.group(3) or '')
                        if lm:
                            sites.append((m.group(1), lm.group(1), int(lm.group(2)), int(lm.group(3))))
                        continue
                    calls.setdefault(m.group(1), {})[m.group(2)] = None
    skipped = {}
    n_hops = 0
    if tables and sites:
        added, skipped, _ = indirect_edges(where, sites, root, kinds)
        for caller, callee, slot in added:
            c = calls.setdefault(caller, {})
            if callee not in c:
                c[callee] = slot
        n_hops = len({(a, b) for a, b, _ in added})
    memo, recursive = {}, set()

    def worst(fn, path):
        if fn in memo:
            return memo[fn]
        if fn in path:
            recursive.add(fn)
            return (0, [])
        path.add(fn)
        best, chain = 0, []
        for callee, hop in calls.get(fn, {}).items():
            w, c = worst(callee, path)
            if w > best:
                best, chain = w, [(callee, hop)] + c[1:] if c else [(callee, hop)]
        path.discard(fn)
        res = (frame.get(fn, 0) + best, [(fn, None)] + chain)
        memo[fn] = res
        return res

    def show(chain, n=10):
        out = ''
        for k, (c, hop) in enumerate(chain[:n]):
            name = c.split(':')[-1]
            out += name if k == 0 else (f' =[{hop}]=> ' if hop else ' > ') + name
        return out + (' > ...' if len(chain) > n else '')

    sys.setrecursionlimit(10000)
    entries = sorted(t for t in frame if t.startswith('kelp_') and ':' not in t)
    rows = [(worst(e, set())[0], e, worst(e, set())[1]) for e in entries]
    rows.sort(key=lambda r: (-r[0], r[1]))
    over = [r for r in rows if r[0] > limit]
    how = ("direct calls only" if not tables else
           f"calls through the core's function tables followed ({n_hops} edges)" if kinds == {'table'} else
           f"calls through the core's tables and its own callbacks followed ({n_hops} edges)")
    print(f"stack: {len(rows)} public core entry points; worst case {rows[0][0] if rows else 0} bytes "
          f"({rows[0][1] if rows else '-'}); {len(over)} over {limit} bytes; {how}")
    shown = over + [r for r in rows[:top] if r not in over]
    for w, e, chain in shown[:max(top, len(over))]:
        print(f"  {w:7d}  {e:42s} {show(chain)}")
    if tables and sites:
        kinds = sorted({s for _, _, s in (added if sites else [])})
        print("  followed through: " + (', '.join(kinds) if kinds else '(none)'))
        own = {k[len('core callback: '):]: v for k, v in skipped.items() if k.startswith('core callback: ')}
        ext = {k: v for k, v in skipped.items() if not k.startswith('core callback: ')}

        def listing(d):
            return ', '.join(f'{k} ({len(v)})' for k, v in sorted(d.items(), key=lambda kv: (-len(kv[1]), kv[0])))
        print(f"  not followed, {sum(len(v) for v in ext.values())} call sites through what the library's caller "
              "supplies (sinks, log callbacks, transports, crypto, the acomms codec view the edge fills): " + listing(ext))
        if own:
            print(f"  not followed, {sum(len(v) for v in own.values())} call sites through the core's own callbacks "
                  "(a function passed as an argument or put in an automatic struct; --callbacks follows them): "
                  + listing(own))
    dyn = sorted(t for t, k in kind.items() if k != 'static')
    if dyn:
        print("  dynamic frames (not bounded at compile time): " + ', '.join(dyn))
    if recursive:
        print("  recursive (one round counted): " + ', '.join(sorted(c.split(':')[-1] for c in recursive)))
    if fail and over:
        print(f"stack: {len(over)} public entry points need more than {limit} bytes")
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))

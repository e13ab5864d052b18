#!/usr/bin/env python3
"""Import cycles between sibling modules of src/ (a `use` of crate:: or super:: paths outside
tests), and imports against the data flow of a folder whose rooms are stages (STAGES): prints
each and exits 1 when there is one. The CLI (src/cli) is left out."""
import os, re, sys
root=os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'src')
mods={}
for dp,_,fs in os.walk(root):
    for f in fs:
        if not f.endswith('.rs') or f in ('main.rs','lib.rs'): continue
        p=os.path.join(dp,f)
        rel=os.path.relpath(p,root)[:-3].split(os.sep)
        if rel[-1]=='mod': rel=rel[:-1]
        mods['::'.join(rel)]=open(p).read()
def resolve(cur, ref):
    # ref like crate::a::b::c or super::x
    return ref
def split_top(s):
    """`a, b::{c, d}, e` split at the commas outside braces."""
    out, depth, cur = [], 0, ''
    for ch in s:
        if ch == '{': depth += 1
        elif ch == '}': depth -= 1
        if ch == ',' and depth == 0:
            out.append(cur); cur = ''
        else:
            cur += ch
    out.append(cur)
    return [x.strip() for x in out if x.strip()]
def expand(tree):
    """The paths of a use tree, brace groups expanded: `super::{a, b::{c}}` -> super::a, super::b::c."""
    tree = re.sub(r'\s+', '', tree)
    i = tree.find('{')
    if i < 0:
        return [re.sub(r'(::self)?$', '', tree.split(' as ')[0])]
    prefix, inner = tree[:i], tree[i+1:tree.rindex('}')]
    out = []
    for part in split_top(inner):
        for p in expand(part):
            out.append(prefix + p if p != 'self' else prefix.rstrip(':'))
    return out
def absolute(parts, path):
    """Module path of `path` seen from module `parts`, or None when not crate-internal."""
    segs = [x for x in path.split('::') if x]
    if not segs: return None
    if segs[0] == 'crate': return segs[1:]
    if segs[0] in ('super', 'self'):
        base = list(parts)
        while segs and segs[0] in ('super', 'self'):
            if segs[0] == 'super': base = base[:-1]
            segs = segs[1:]
        return base + segs
    return None
edges=set()
for m,src in mods.items():
    if m.startswith('cli'): continue
    # strip comments
    code='\n'.join(l for l in src.split('\n') if not l.strip().startswith('//'))
    # cut tests
    i=code.find('#[cfg(test)]')
    if i>=0: code=code[:i]
    parts=m.split('::')
    refs=[]
    # `use` statements, brace groups expanded (a group names each sibling it imports).
    for u in re.findall(r'\buse\s+([^;]+);', code):
        refs.extend(expand(u))
    # Paths written inline.
    refs.extend(re.findall(r'\b((?:crate|super)(?:::[a-z_]+)+)', code))
    for r in refs:
        a = absolute(parts, r)
        if a:
            edges.add((m, '::'.join(a)))
# for each parent, sibling graph
def sib_graph():
    g={}
    for a,b in edges:
        A=a.split('::'); B=b.split('::')
        # common prefix
        k=0
        while k<min(len(A),len(B)) and A[k]==B[k]: k+=1
        if k<len(A) and k<len(B):
            pa='::'.join(A[:k]); x=A[k]; y=B[k]
            if '::'.join(B[:k+1]) in mods or True:
                g.setdefault(pa,{}).setdefault(x,set()).add(y)
        elif k==len(B) and k<len(A):
            # child referencing ancestor module item: child -> parent
            g.setdefault('::'.join(B[:-1]) if len(B)>1 else '',{}).setdefault(A[len(B)-1] if len(B)-1 < len(A) else A[-1],set())
    return g
g=sib_graph()
def find_cycles(adj):
    cyc=[]
    nodes=list(adj)
    for n in nodes:
        # DFS for cycle back to n
        stack=[(n,[n])]
        seen=set()
        while stack:
            v,path=stack.pop()
            for w in adj.get(v,()):
                if w==n and len(path)>1: cyc.append(path+[n])
                elif w not in path and (w,len(path)) not in seen and len(path)<6:
                    seen.add((w,len(path)))
                    stack.append((w,path+[w]))
    return cyc
# Folders whose rooms are stages in data-flow order: a room imports only rooms before it, so
# that a walk of the data (and of the options it carries) never returns to a room it left.
# `error` and `options` sit after the stages whose types they name, before those that read them.
STAGES={'design': ['trajectory','inverse','hypothesis','fit','error','options','strategy',
                   'train','report','chain','tradeoff']}
found=False
for parent,order in STAGES.items():
    for a,b in sorted(g.get(parent,{}).items()):
        for x in sorted(b):
            if a in order and x in order and order.index(x)>order.index(a):
                print(f"against the flow in `{parent}`: {a} imports {x}, a later stage "
                      f"(order: {' -> '.join(order)})"); found=True
for parent,adj in sorted(g.items()):
    adj={k:{x for x in v if x!=k} for k,v in adj.items()}
    cs=find_cycles(adj)
    uniq=set()
    for c in cs:
        key=frozenset(c)
        if key in uniq: continue
        uniq.add(key)
        print(f"cycle in `{parent or 'crate'}`: {' -> '.join(c)}"); found=True
print('no import cycles between sibling modules' if not found else '')
sys.exit(1 if found else 0)

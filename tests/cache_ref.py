#!/usr/bin/env python3
"""Reference model of a set-associative cache, independent of the C++ one (plain Python).

usage: cache_ref.py TRACE SIZE ASSOC LINE POLICY[,POLICY...]
TRACE is Dinero IV din format, one "0 <hex address>" line per read. Prints "POLICY MISSES"
per policy. Policies: lru, fifo, tree-plru. Invalid ways are filled first, lowest way first.
tree-plru: one bit per internal node of a binary tree over the ways (root 1, children 2n and
2n+1, way w is leaf ASSOC+w); bit 0 = left half older, 1 = right half older; a use points the
bits on its path away from it; the victim follows the bits from the root.
"""
import sys


def misses(addrs, size, assoc, line, policy):
    nsets = size // (line * assoc)
    sets = [[] for _ in range(nsets)]        # lru/fifo: tags, oldest first
    ways = [[None] * assoc for _ in range(nsets)]  # tree-plru: tag per way
    bits = [[0] * assoc for _ in range(nsets)]     # tree-plru: bits[node], node 1..assoc-1
    count = 0
    for a in addrs:
        block = a // line
        s, tag = block % nsets, block // nsets
        if policy in ("lru", "fifo"):
            q = sets[s]
            if tag in q:
                if policy == "lru":
                    q.remove(tag)
                    q.append(tag)
                continue
            count += 1
            if len(q) == assoc:
                q.pop(0)
            q.append(tag)
        elif policy == "tree-plru":
            w = ways[s]
            if tag in w:
                way = w.index(tag)
            else:
                count += 1
                if None in w:
                    way = w.index(None)
                else:
                    node = 1
                    while node < assoc:
                        node = 2 * node + bits[s][node]
                    way = node - assoc
                w[way] = tag
            node = assoc + way                 # walk up from the leaf
            while node > 1:
                parent = node // 2
                bits[s][parent] = 1 if node == 2 * parent else 0  # point at the other child
                node = parent
        else:
            sys.exit("unknown policy " + policy)
    return count


def main():
    if len(sys.argv) != 6:
        sys.exit(__doc__)
    with open(sys.argv[1]) as f:
        addrs = [int(line.split()[1], 16) for line in f if line.strip()]
    size, assoc, line = int(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
    for policy in sys.argv[5].split(","):
        print(policy, misses(addrs, size, assoc, line, policy))


if __name__ == "__main__":
    main()

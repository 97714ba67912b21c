#!/usr/bin/env python3
"""Reference model of a set-associative cache, independent of the C++ one (plain Python).

usage: cache_ref.py TRACE SIZE ASSOC LINE POLICY[,POLICY...] [SEED]
TRACE is Dinero IV din format, one "0 <hex address>" line per read. Prints "POLICY MISSES"
per policy. Policies: lru, fifo, tree-plru, random. Invalid ways are filled first, lowest way
first. ASSOC "full" is SIZE / LINE ways in one set.
tree-plru: one bit per internal node of a binary tree over the ways (root 1, children 2n and
2n+1, way w is leaf ASSOC+w); bit 0 = left half older, 1 = right half older; a use points the
bits on its path away from it; the victim follows the bits from the root.
random: one splitmix64 stream per cache, state SEED (default 1, l1.seed's default); each
eviction (a miss in a full set) draws once, and the victim is way (top 32 bits x ASSOC) >> 32.
"""
import sys

MASK64 = (1 << 64) - 1


class SplitMix64:
    """splitmix64 (Steele, Lea, Flood 2014), written from the paper's constants."""

    def __init__(self, seed):
        self.state = seed & MASK64

    def next(self):
        self.state = (self.state + 0x9E3779B97F4A7C15) & MASK64
        z = self.state
        z = ((z ^ (z >> 30)) * 0xBF58476D1CE4E5B9) & MASK64
        z = ((z ^ (z >> 27)) * 0x94D049BB133111EB) & MASK64
        return z ^ (z >> 31)

    def below(self, n):
        return ((self.next() >> 32) * n) >> 32


def misses(addrs, size, assoc, line, policy, seed=1):
    nsets = size // (line * assoc)
    sets = [[] for _ in range(nsets)]        # lru/fifo: tags, oldest first
    ways = [[None] * assoc for _ in range(nsets)]  # tree-plru: tag per way
    bits = [[0] * assoc for _ in range(nsets)]     # tree-plru: bits[node], node 1..assoc-1
    rng = SplitMix64(seed)                         # random: one stream per cache
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
        elif policy == "random":
            w = ways[s]
            if tag in w:
                continue
            count += 1
            w[w.index(None) if None in w else rng.below(assoc)] = tag
        else:
            sys.exit("unknown policy " + policy)
    return count


def main():
    if len(sys.argv) not in (6, 7):
        sys.exit(__doc__)
    with open(sys.argv[1]) as f:
        addrs = [int(line.split()[1], 16) for line in f if line.strip()]
    size, line = int(sys.argv[2]), int(sys.argv[4])
    assoc = size // line if sys.argv[3] == "full" else int(sys.argv[3])
    seed = int(sys.argv[6]) if len(sys.argv) == 7 else 1
    for policy in sys.argv[5].split(","):
        print(policy, misses(addrs, size, assoc, line, policy, seed))


if __name__ == "__main__":
    main()

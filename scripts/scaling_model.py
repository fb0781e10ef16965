#!/usr/bin/env python3
"""Weak-scaling model of a settle run across many processes (docs/parallel.md, "Speed").

Reads the JSON of `mpirun -n 2 settle bench ...` (the kernel box or --case), checks the model's
ghost-byte count against the bytes the communicator counted, and predicts the time per step and
the weak-scaling efficiency for 64 to 1024 processes on a cluster network:

  every process holds a cube of B^3 cells (its share of a lattice that grows with N) and steps it
  at R cell updates per second; with a 3-D split it exchanges with 6 face neighbours (and 12 edge
  neighbours for D3Q19, plus 8 corners for D3Q27); the messages' time is counted in full, as if
  none of it were hidden behind the interior update (settle posts them before it, but no gain was
  measurable on one machine), so a step takes

    t(N) = B^3 / R + n_msg alpha + halo_bytes / beta + t_body(N) + t_agree(N)

  with alpha the message latency and beta the link bandwidth. The body's collective (the
  immersed boundary's forcing box, or the momentum exchange's link momenta, gathered on every
  rank) and the per-step agreement on signals (two numbers per rank) are all-gathers:
  ceil(log2 N) alpha + gathered_bytes / beta. Efficiency E(N) = (B^3 / R) / t(N): one process
  of the same block has no messages.

Figures from the bench: R (the mean of the ranks' MLUPS) unless --mlups-per-rank is given, the
body's gathered bytes per step (the sum over the ranks of what each contributed). Assumptions
(arguments): B, alpha, beta. Prints a table; exits 1 if the bench's ghost bytes disagree with the
model's count for the bench's own split (the count is exact, so any difference is a model error).
"""
import argparse
import json
import math
import sys

# Populations of a lattice that cross a face, an edge and a corner of a block.
CROSSING = {"D3Q19": (5, 1, 0), "D3Q27": (9, 3, 1)}


def halo_per_step(lattice, block, faces, edges, corners, value_bytes=8):
    """Bytes and messages one rank sends per step (messages carry doubles)."""
    face, edge, corner = CROSSING[lattice]
    values = faces * face * block[1] * block[2] + edges * edge * block[0] + corners * corner
    return values * value_bytes


def bench_face_bytes(bench):
    """The model's count for the bench's own split (1 x 1 x 2 of a periodic box: two shared faces)."""
    blocks = bench["split_blocks"]
    if blocks != [1, 1, 2] or "case" in bench:  # a case's walls carry fewer populations at their edges
        return None
    cells = bench.get("cells")
    if isinstance(cells, list):
        nx, ny = cells[0], cells[1]
    else:
        nx = ny = round(cells ** (1.0 / 3.0))
    face, _, _ = CROSSING[bench["lattice"]]
    return 2 * face * nx * ny * 8


def allgather_seconds(ranks, gathered_bytes, alpha, beta):
    return math.ceil(math.log2(ranks)) * alpha + gathered_bytes / beta if ranks > 1 else 0.0


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("bench_json", help="output of `mpirun -n 2 settle bench ...`")
    parser.add_argument("--block", type=int, default=128, help="cells per edge of each process's cube (B)")
    parser.add_argument("--latency-us", type=float, default=2.0, help="message latency alpha, microseconds")
    parser.add_argument("--bandwidth-gbs", type=float, default=12.0, help="link bandwidth beta, GB/s")
    parser.add_argument("--mlups-per-rank", type=float, default=None,
                        help="cell updates per second of one process (default: the bench's mean)")
    args = parser.parse_args()

    with open(args.bench_json) as f:
        bench = json.load(f)
    if "ranks" not in bench:
        sys.exit("scaling_model: the bench ran in one process; run it under mpirun -n 2")
    ranks = bench["ranks"]
    lattice = bench["lattice"]
    measured = ranks[0]["ghost_bytes_sent_per_step"]
    expected = bench_face_bytes(bench)
    status = 0
    if expected is not None:
        agree = "agrees" if expected == measured else "DISAGREES"
        print(f"ghost bytes per step on the bench's split: model {expected:.0f}, counted {measured:.0f}: {agree}")
        status = 0 if expected == measured else 1

    rate = args.mlups_per_rank * 1e6 if args.mlups_per_rank else 1e6 * sum(r["mlups"] for r in ranks) / len(ranks)
    body_bytes = sum(r.get("collective_bytes_sent_per_step", 0.0) for r in ranks)
    alpha, beta = args.latency_us * 1e-6, args.bandwidth_gbs * 1e9
    b = args.block
    compute = b ** 3 / rate
    corners = 8 if lattice == "D3Q27" else 0
    halo_bytes = halo_per_step(lattice, (b, b, b), 6, 12, corners)
    messages = 6 + 12 + corners
    halo = messages * alpha + halo_bytes / beta
    print(f"assumed: {b}^3 cells per process at {rate / 1e6:.1f} MLUPS, latency {args.latency_us} us, "
          f"bandwidth {args.bandwidth_gbs} GB/s; halo {halo_bytes / 1e6:.2f} MB in {messages} messages per step; "
          f"body collective {body_bytes / 1e3:.1f} kB per step (measured)")
    print(f"{'processes':>9} {'compute ms':>10} {'halo ms':>8} {'body ms':>8} {'agree ms':>8} {'efficiency':>10}")
    for n in (2, 64, 128, 256, 512, 1024):
        body = allgather_seconds(n, body_bytes, alpha, beta)
        agree = allgather_seconds(n, 16.0 * n, alpha, beta)
        total = compute + halo + body + agree
        print(f"{n:>9} {compute * 1e3:>10.2f} {halo * 1e3:>8.3f} {body * 1e3:>8.3f} {agree * 1e3:>8.3f} "
              f"{compute / total:>10.3f}")
    return status


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
"""PyTorch (CPU) side of bench/mlp_vs_torch.sh: trains the same network as
`skyfit fit mlp` on the same CSV from the same initial weights (a skyfit
weights file, W0/b0/...), Adam lr 0.01, MSE, sigmoid hidden and exp(-x)
output, and prints seconds per epoch and the final training MSE as JSON."""
import argparse
import json
import time

import numpy as np
import torch


def main():
    p = argparse.ArgumentParser()
    p.add_argument("--data", required=True)
    p.add_argument("--inputs", type=int, required=True)
    p.add_argument("--init", required=True)
    p.add_argument("--epochs", type=int, required=True)
    p.add_argument("--batch", type=int, required=True, help="0: full batch")
    p.add_argument("--threads", type=int, default=1)
    p.add_argument("--seed", type=int, default=1)
    a = p.parse_args()
    torch.set_num_threads(a.threads)
    torch.manual_seed(a.seed)
    data = np.loadtxt(a.data, delimiter=",", skiprows=1, dtype=np.float64)
    x = torch.from_numpy(np.ascontiguousarray(data[:, : a.inputs]))
    y = torch.from_numpy(np.ascontiguousarray(data[:, a.inputs :]))
    w = json.load(open(a.init))
    n_layers = len([k for k in w["params"] if k.startswith("W")])
    layers = []
    for l in range(n_layers):
        W = torch.tensor(w["params"]["W%d" % l], dtype=torch.float64)
        b = torch.tensor(w["params"]["b%d" % l], dtype=torch.float64)
        lin = torch.nn.Linear(W.shape[1], W.shape[0]).double()
        with torch.no_grad():
            lin.weight.copy_(W)
            lin.bias.copy_(b)
        layers.append(lin)
    params = [q for lin in layers for q in lin.parameters()]

    def forward(inp):
        a_ = inp
        for l, lin in enumerate(layers):
            z = lin(a_)
            a_ = torch.exp(-z) if l + 1 == len(layers) else torch.sigmoid(z)
        return a_

    opt = torch.optim.Adam(params, lr=0.01, betas=(0.9, 0.999), eps=1e-8)
    n = x.shape[0]
    batch = a.batch if 0 < a.batch < n else n
    t0 = time.perf_counter()
    c0 = time.process_time()
    for epoch in range(a.epochs):
        # A full batch is not shuffled (skyfit does not shuffle it either):
        # its gradient is the same sum in any order, and a permuted copy of
        # the whole set each epoch would slow PyTorch down for nothing.
        perm = torch.randperm(n) if batch < n else None
        for s in range(0, n, batch):
            xb, yb = (x[perm[s : s + batch]], y[perm[s : s + batch]]) if perm is not None else (x, y)
            opt.zero_grad(set_to_none=True)
            loss = torch.mean((forward(xb) - yb) ** 2)
            loss.backward()
            opt.step()
    dt = (time.perf_counter() - t0) / a.epochs
    dc = (time.process_time() - c0) / a.epochs
    with torch.no_grad():
        mse = torch.mean((forward(x) - y) ** 2).item()
    print(json.dumps({"final_train_mse": mse, "seconds_per_epoch": dt, "cpu_seconds_per_epoch": dc, "epochs": a.epochs, "samples": n,
                      "batch": a.batch, "threads": a.threads, "torch": torch.__version__}))


if __name__ == "__main__":
    main()

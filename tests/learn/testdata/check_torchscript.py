"""Loads a Podium TorchScript policy with Python's torch and compares its actions with the C++
ones. Usage: check_torchscript.py MODEL.pt CASES.json; exit 0 when they agree to 1e-5."""
import json
import sys

import torch

model = torch.jit.load(sys.argv[1])
with open(sys.argv[2]) as f:
    cases = json.load(f)
obs = torch.tensor(cases["observations"], dtype=torch.float32)
expected = torch.tensor(cases["actions"], dtype=torch.float64)
with torch.no_grad():
    actions = model(obs).to(torch.float64)
diff = (actions - expected).abs().max().item()
print(f"{len(obs)} observations, max |python - c++| = {diff:.3g}")
sys.exit(0 if actions.shape == expected.shape and diff <= 1e-5 else 1)

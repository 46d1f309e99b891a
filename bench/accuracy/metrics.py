"""Per-run accuracy record, computed here from the masks and the labels (independently of the
report al-refine writes): F1 before/after, raised, misses recovered, precision of the added,
restored count and precision."""
import numpy as np


def f1(mask, target):
    tp = int(np.sum(mask & target))
    denom = int(mask.sum()) + int(target.sum())
    return 2.0 * tp / denom if denom else 1.0


def record(removed, refined, target):
    added = refined & ~removed
    restored = removed & ~refined
    misses = target & ~removed                 # the method's false negatives
    over = removed & ~target                   # the method's false positives
    n_added, n_restored = int(added.sum()), int(restored.sum())
    added_true = int(np.sum(added & target))
    restored_true = int(np.sum(restored & ~target))
    before, after = f1(removed, target), f1(refined, target)
    return {
        "f1_before": before,
        "f1_after": after,
        "dF1": after - before,
        "raised": after > before + 1e-12,
        "lowered_001": after < before - 0.01,
        "removed": int(removed.sum()),
        "target": int(target.sum()),
        "misses": int(misses.sum()),
        "over_removed": int(over.sum()),
        "added": n_added,
        "added_true": added_true,
        "misses_recovered": added_true / int(misses.sum()) if misses.any() else None,
        "precision_added": added_true / n_added if n_added else None,
        "restored": n_restored,
        "restored_true": restored_true,
        "over_removed_restored": restored_true / int(over.sum()) if over.any() else None,
        "precision_restored": restored_true / n_restored if n_restored else None,
    }

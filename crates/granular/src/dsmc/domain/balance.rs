//! Load balance of the slab decomposition: how the cuts between ranks follow the grains
//! (`dsmc.balance`), by count or by measured time.

/// How the slab cuts follow the grains (`Domain::rebalance`): the scenario's
/// `dsmc.balance`. The cuts never change the result (see the module docs), only how the
/// work is shared.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum BalanceMode {
    /// Fixed cuts: equal numbers of cell planes per rank.
    Off,
    /// Cuts that give every rank about the same number of grains (default).
    #[default]
    Count,
    /// Cuts that give every rank about the same measured compute time: a plane's load is
    /// its grains times its owner's measured seconds per grain since the last re-cut.
    Time,
}

/// When and by what the slab cuts move.
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Balance {
    /// By what.
    pub mode: BalanceMode,
    /// Steps between two looks at the load (`dsmc.balance_every`); the cuts move when the
    /// most loaded rank carries more than `IMBALANCE` times the mean.
    pub every: u64,
}

impl Default for Balance {
    fn default() -> Balance {
        Balance {
            mode: BalanceMode::Count,
            every: 20,
        }
    }
}

/// The ratio of the largest rank load to the mean above which the cuts move.
pub(crate) const IMBALANCE: f64 = 1.05;

/// The cuts that share `loads` (one per plane, in plane order) over `k` ranks as evenly
/// as whole planes allow, every rank at least one plane: rank `r` gets the planes
/// `cuts[r] .. cuts[r + 1]`, each cut where the running load is nearest `r / k` of the
/// total.
pub(crate) fn balanced_cuts(loads: &[f64], k: usize) -> Vec<usize> {
    let p = loads.len();
    let total: f64 = loads.iter().sum();
    let mut cuts = vec![0; k + 1];
    cuts[k] = p;
    let mut prefix = 0.0;
    let mut plane = 0;
    for r in 1..k {
        let target = total * r as f64 / k as f64;
        while plane < p && prefix + loads[plane] <= target {
            prefix += loads[plane];
            plane += 1;
        }
        // The nearer of the cuts before and after the plane that crosses the target.
        let mut cut = plane;
        if plane < p && (prefix + loads[plane] - target) < (target - prefix) {
            cut = plane + 1;
        }
        cuts[r] = cut.clamp(cuts[r - 1] + 1, p - (k - r));
    }
    cuts
}

/// Most grains a rank may get from cuts by measured time ([`BalanceMode::Time`]), as a
/// multiple of the mean `N / K`: on a busy machine a rank may measure itself fast for a
/// while (its neighbours were descheduled), and without a bound the cuts could hand it
/// nearly every grain, and its memory with them.
pub const TIME_SHARE_CAP: f64 = 2.0;

/// The cuts by measured time: [`balanced_cuts`] of the planes' `loads` (grains times
/// their owner's seconds per grain), unless a rank would then own more than
/// [`TIME_SHARE_CAP`] times the mean grains (`counts`: grains per plane), when the cuts
/// share the grains instead.
pub(crate) fn time_cuts(counts: &[f64], loads: &[f64], k: usize) -> Vec<usize> {
    let cuts = balanced_cuts(loads, k);
    let cap = TIME_SHARE_CAP * counts.iter().sum::<f64>() / k as f64;
    if cuts
        .windows(2)
        .all(|w| counts[w[0]..w[1]].iter().sum::<f64>() <= cap)
    {
        cuts
    } else {
        balanced_cuts(counts, k)
    }
}

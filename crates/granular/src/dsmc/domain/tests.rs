//! The decomposition's unit tests (in-process ranks).

use super::*;
use std::collections::VecDeque;
use std::sync::{Barrier, Condvar};

/// `K` ranks as threads of this process (as the integration tests' communicator).
#[derive(Debug)]
struct InProcess {
    rank: usize,
    shared: Arc<Shared>,
}

#[derive(Debug)]
struct Shared {
    size: usize,
    barrier: Barrier,
    /// `slots[from][to]` of a collective.
    slots: Mutex<Vec<Vec<Vec<f64>>>>,
    /// Point-to-point messages, `mail[from * size + to]`, oldest first.
    mail: Mutex<Vec<VecDeque<Vec<f64>>>>,
    posted: Condvar,
}

fn world(size: usize) -> Vec<InProcess> {
    let shared = Arc::new(Shared {
        size,
        barrier: Barrier::new(size),
        slots: Mutex::new(vec![vec![Vec::new(); size]; size]),
        mail: Mutex::new(vec![VecDeque::new(); size * size]),
        posted: Condvar::new(),
    });
    (0..size)
        .map(|rank| InProcess {
            rank,
            shared: shared.clone(),
        })
        .collect()
}

impl Communicator for InProcess {
    fn rank(&self) -> usize {
        self.rank
    }

    fn size(&self) -> usize {
        self.shared.size
    }

    fn all_gather(&self, local: &[f64]) -> Vec<Vec<f64>> {
        self.exchange(vec![local.to_vec(); self.size()])
    }

    fn exchange(&self, outgoing: Vec<Vec<f64>>) -> Vec<Vec<f64>> {
        self.shared.slots.lock().unwrap()[self.rank] = outgoing;
        self.shared.barrier.wait();
        let received = self
            .shared
            .slots
            .lock()
            .unwrap()
            .iter()
            .map(|row| row[self.rank].clone())
            .collect();
        self.shared.barrier.wait();
        received
    }

    fn send(&self, to: usize, words: &[f64]) {
        let mut mail = self.shared.mail.lock().unwrap();
        mail[self.rank * self.shared.size + to].push_back(words.to_vec());
        self.shared.posted.notify_all();
    }

    fn receive(&self, from: usize) -> Vec<f64> {
        let mut mail = self.shared.mail.lock().unwrap();
        loop {
            if let Some(words) = mail[from * self.shared.size + self.rank].pop_front() {
                return words;
            }
            mail = self.shared.posted.wait(mail).unwrap();
        }
    }
}

/// Values whose sum depends on the order of addition: magnitudes from 1e-6 to 1e6.
fn values(n: usize) -> Vec<[f64; 2]> {
    (0..n)
        .map(|i| {
            let x = i as f64;
            let scale = 10f64.powi((i % 13) as i32 - 6);
            [(0.37 * x).sin() * scale, (1.3 * x + 0.2).cos() / scale]
        })
        .collect()
}

/// The threaded engine's sum: chunks of `SUM_CHUNK` folded in parallel, then added in
/// order (as `DsmcEngine::peculiar_moments`: accumulates `x` and `x^2` of component 0
/// and the vector sum).
fn threaded(v: &[[f64; 2]]) -> [f64; 4] {
    v.par_chunks(SUM_CHUNK)
        .map(|c| {
            c.iter().fold([0.0; 4], |a, x| {
                [a[0] + x[0], a[1] + x[0] * x[0], a[2] + x[0], a[3] + x[1]]
            })
        })
        .collect::<Vec<_>>()
        .into_iter()
        .fold([0.0; 4], |a, c| {
            [a[0] + c[0], a[1] + c[1], a[2] + c[2], a[3] + c[3]]
        })
}

/// The chained messages a layout needs: per chunk, the ranks with particles it spans,
/// minus one.
fn chain_messages(counts: &[usize]) -> u64 {
    let total: usize = counts.iter().sum();
    let mut owner = Vec::with_capacity(total);
    for (r, &c) in counts.iter().enumerate() {
        owner.extend(std::iter::repeat_n(r, c));
    }
    owner
        .chunks(SUM_CHUNK)
        .map(|c| c.windows(2).filter(|w| w[0] != w[1]).count() as u64)
        .sum()
}

/// Every rank's result and traffic of the decomposed fold of `values(sum counts)`
/// split as `counts`.
fn decomposed(counts: &[usize]) -> Vec<([f64; 4], Traffic)> {
    let all = values(counts.iter().sum());
    let k = counts.len();
    std::thread::scope(|s| {
        let handles: Vec<_> = world(k)
            .into_iter()
            .map(|comm| {
                let all = &all;
                s.spawn(move || {
                    let r = comm.rank;
                    let d = Domain::new(Arc::new(comm), &[1, k], all.len()).unwrap();
                    let offset: usize = counts[..r].iter().sum();
                    let mine = &all[offset..offset + counts[r]];
                    let [a, b] = d.ordered_fold::<1, 2>(
                        mine.len(),
                        |i| [mine[i][0]],
                        |a, &[x]| *a = [a[0] + x, a[1] + x * x],
                        |a, x| *a = [a[0] + x[0], a[1] + x[1]],
                    );
                    let [c, e] = d.ordered_fold::<2, 2>(
                        mine.len(),
                        |i| mine[i],
                        |a, x| *a = [a[0] + x[0], a[1] + x[1]],
                        |a, x| *a = [a[0] + x[0], a[1] + x[1]],
                    );
                    ([a, b, c, e], d.traffic())
                })
            })
            .collect();
        handles.into_iter().map(|h| h.join().unwrap()).collect()
    })
}

/// The chained fold gives the threaded engine's bits on every rank, for layouts where
/// chunks span 3 and more ranks, ranks hold no particles, and cuts fall on chunk
/// boundaries; the traffic is the layout's: per sum one count and one accumulator per
/// chunk gathered, and one accumulator per rank a chunk passes on to.
#[test]
fn chained_fold_is_the_threaded_fold_bit_for_bit() {
    let layouts: [&[usize]; 12] = [
        &[10_000],
        &[5000, 0, 10, 3000, 2000, 0, 9000],
        &[1, 1, 1, 1, 1],
        &[0, 0, 7],
        &[7, 0, 0],
        &[4096, 4096, 0, 4096],
        &[4095, 2, 4095, 4097],
        &[3, 0, 0, 0, 4100],
        &[0, 0, 0],
        &[1000, 1000, 0, 1000, 1000, 1000, 0],
        &[250_000, 250_000],
        &[9000, 1, 0, 1, 9000],
    ];
    // The data is order-sensitive: a plain running sum differs from the chunked one.
    let v = values(10_000);
    let plain: f64 = v.iter().fold(0.0, |a, x| a + x[0] * x[0]);
    assert_ne!(plain.to_bits(), threaded(&v)[1].to_bits());
    for counts in layouts {
        let total: usize = counts.iter().sum();
        let want = threaded(&values(total)).map(f64::to_bits);
        let k = counts.len() as u64;
        let chunks = total.div_ceil(SUM_CHUNK) as u64;
        let results = decomposed(counts);
        let mut messages = 0;
        let mut sent = 0;
        for (rank, (got, t)) in results.iter().enumerate() {
            assert_eq!(got.map(f64::to_bits), want, "{counts:?}: rank {rank}");
            messages += t.reduction_messages;
            sent += t.reduction_bytes_sent;
            assert_eq!(t.reduction_calls, 4, "{counts:?}: rank {rank}");
        }
        let chain = chain_messages(counts);
        assert_eq!(messages, 2 * chain, "{counts:?}");
        // Two sums: counts (1 word to each other rank), the accumulators of every
        // chunk (2 words to each other rank), the chained accumulators (2 words).
        assert_eq!(
            sent,
            2 * 8 * (k * (k - 1) + 2 * chunks * (k - 1) + 2 * chain),
            "{counts:?}"
        );
    }
}

/// The cuts share the load as evenly as whole planes allow, every rank at least one
/// plane, and a domain reads them back.
#[test]
fn balanced_cuts_follow_the_load() {
    // Even load: equal slabs.
    assert_eq!(balanced_cuts(&[1.0; 12], 4), vec![0, 3, 6, 9, 12]);
    // Everything in the last two planes: one each for two ranks, the empty rest for one.
    let mut loads = vec![0.0; 10];
    loads[8] = 5.0;
    loads[9] = 5.0;
    assert_eq!(balanced_cuts(&loads, 3), vec![0, 8, 9, 10]);
    // A cluster in the middle: the cuts close in on it.
    let loads = [1.0, 1.0, 10.0, 10.0, 10.0, 10.0, 1.0, 1.0];
    let cuts = balanced_cuts(&loads, 4);
    assert_eq!(cuts, vec![0, 3, 4, 5, 8]);
    let mut d = Domain::for_ids(Arc::new(world(4).remove(2)), 100)
        .with_grid(&[3, 8])
        .unwrap();
    d.set_cuts(&cuts);
    assert_eq!(d.cuts(), cuts);
    assert_eq!(d.own_planes(), 4..5);
    assert_eq!(d.cells, 12..15);
    assert_eq!(
        (d.owner(0), d.owner(9), d.owner(12), d.owner(23)),
        (0, 1, 2, 3)
    );
}

/// Cuts by time follow the measured cost, but never give a rank more than
/// `TIME_SHARE_CAP` times the mean grains, however fast it measured itself.
#[test]
fn time_cuts_are_capped_by_grains() {
    let counts = [10.0; 8];
    // Rank 0 (planes 0..2) twice as slow as the others: it gets fewer planes.
    let mut loads = counts;
    loads[0] *= 2.0;
    loads[1] *= 2.0;
    assert_eq!(time_cuts(&counts, &loads, 4), balanced_cuts(&loads, 4));
    assert_eq!(time_cuts(&counts, &loads, 4)[1], 1);
    // Rank 3 (planes 6..8) measured (by noise) a thousand times slower: by time rank 0
    // would take five planes of eight (2.5 times the mean grains), so the cuts share
    // the grains instead.
    let mut loads = counts;
    loads[6] *= 1000.0;
    loads[7] *= 1000.0;
    assert_eq!(balanced_cuts(&loads, 4), vec![0, 5, 6, 7, 8]);
    assert_eq!(time_cuts(&counts, &loads, 4), vec![0, 2, 4, 6, 8]);
}

#[test]
fn chain_layout_skips_empty_ranks() {
    let counts = [4095, 0, 2, 0, 4097];
    let l: Vec<ChainLayout> = (0..5).map(|r| ChainLayout::new(&counts, r)).collect();
    assert_eq!((l[0].head, l[0].open, l[0].next), (0, true, Some(2)));
    assert_eq!((l[1].previous, l[1].next), (None, None));
    assert_eq!((l[2].head, l[2].previous, l[2].next), (1, Some(0), Some(4)));
    assert_eq!(l[2].own_chunks(), vec![1..2]);
    assert_eq!(
        (l[4].head, l[4].previous, l[4].open),
        (4095, Some(2), false)
    );
    assert_eq!(l[4].own_chunks(), vec![4095..4097]);
}

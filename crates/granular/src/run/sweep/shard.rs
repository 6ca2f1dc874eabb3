//! Shards of a sweep: `--shard I/N` (or a job array's environment) runs members
//! `m` with `m mod N = I - 1` (members numbered point by point, seed by seed), so that N
//! independent processes together run every member once.

use std::fmt;
use std::str::FromStr;

/// Share `index` of `count` (1-based: `1/3`, `2/3`, `3/3`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// Which share, 1 to `count`.
    pub index: usize,
    /// Number of shares, at least 1.
    pub count: usize,
}

impl Shard {
    /// The whole sweep, as one shard.
    pub const ALL: Shard = Shard { index: 1, count: 1 };

    /// Whether member number `member` (point-major, then seed) belongs to this shard.
    pub(crate) fn owns(&self, member: usize) -> bool {
        member % self.count == self.index - 1
    }

    /// The shard named by the environment, when `--shard` is not given: `GRANULAR_SHARD`
    /// (`I/N`), else a Slurm job array (`SLURM_ARRAY_TASK_ID` with
    /// `SLURM_ARRAY_TASK_COUNT`, and `SLURM_ARRAY_TASK_MIN`/`_STEP` when present: task
    /// `MIN + (I - 1) * STEP` is shard `I`). Returns the shard and where it came from;
    /// `None` outside a job array.
    pub fn from_env(
        var: impl Fn(&str) -> Option<String>,
    ) -> Result<Option<(Shard, String)>, String> {
        if let Some(text) = var("GRANULAR_SHARD") {
            return Shard::from_str(&text)
                .map(|s| Some((s, format!("GRANULAR_SHARD={text}"))))
                .map_err(|e| format!("GRANULAR_SHARD={text}: {e}"));
        }
        let Some(id) = var("SLURM_ARRAY_TASK_ID") else {
            return Ok(None);
        };
        let number = |name: &str, default: Option<u64>| -> Result<u64, String> {
            match var(name) {
                Some(v) => v.trim().parse::<u64>().map_err(|_| {
                    format!("{name}={v} is not a whole number; give --shard I/N instead")
                }),
                None => default.ok_or_else(|| {
                    format!(
                        "SLURM_ARRAY_TASK_ID={id} is set but {name} is not; run under \
                         `sbatch --array` or give --shard I/N"
                    )
                }),
            }
        };
        let task = number("SLURM_ARRAY_TASK_ID", None)?;
        let count = number("SLURM_ARRAY_TASK_COUNT", None)?;
        let min = number("SLURM_ARRAY_TASK_MIN", Some(0))?;
        let step = number("SLURM_ARRAY_TASK_STEP", Some(1))?.max(1);
        let offset = task.checked_sub(min).filter(|o| o % step == 0);
        let index = offset.map(|o| o / step + 1).filter(|&i| i <= count);
        let (Some(index), true) = (index, count >= 1) else {
            return Err(format!(
                "SLURM_ARRAY_TASK_ID={task} is not task 1 to {count} of the array \
                 (SLURM_ARRAY_TASK_MIN={min}, SLURM_ARRAY_TASK_STEP={step}); give the array as \
                 one range (e.g. --array=0-{}) or pass --shard I/N",
                count.saturating_sub(1)
            ));
        };
        let shard = Shard {
            index: index as usize,
            count: count as usize,
        };
        Ok(Some((shard, format!("SLURM_ARRAY_TASK_ID={task}"))))
    }
}

impl FromStr for Shard {
    type Err = String;

    /// Reads `I/N`: whole numbers with `1 <= I <= N`.
    fn from_str(text: &str) -> Result<Shard, String> {
        let usage = "write the shard as I/N with whole numbers 1 <= I <= N, e.g. 2/8 for the \
                     second of eight shares";
        let (i, n) = text
            .split_once('/')
            .ok_or_else(|| format!("\"{text}\" has no '/'; {usage}"))?;
        let parse = |s: &str, what: &str| {
            s.trim()
                .parse::<usize>()
                .map_err(|_| format!("{what} \"{s}\" is not a whole number; {usage}"))
        };
        let (index, count) = (parse(i, "the shard index")?, parse(n, "the shard count")?);
        if count == 0 {
            return Err(format!("the shard count is 0; {usage}"));
        }
        if index == 0 || index > count {
            return Err(format!(
                "shard {index} of {count} does not exist: shards are numbered 1 to {count} \
                 (e.g. {}/{count})",
                index.clamp(1, count)
            ));
        }
        Ok(Shard { index, count })
    }
}

impl fmt::Display for Shard {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}/{}", self.index, self.count)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn env<'a>(pairs: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |k| pairs.iter().find(|p| p.0 == k).map(|p| p.1.to_string())
    }

    #[test]
    fn shards_split_members_round_robin_and_cover_each_once() {
        let shards: Vec<Shard> = (1..=3).map(|i| Shard { index: i, count: 3 }).collect();
        for m in 0..10 {
            assert_eq!(shards.iter().filter(|s| s.owns(m)).count(), 1);
        }
        assert!(shards[1].owns(4) && Shard::ALL.owns(7));
    }

    #[test]
    fn bad_shards_say_what_is_wrong() {
        assert_eq!("2/3".parse(), Ok(Shard { index: 2, count: 3 }));
        let err = |t: &str| t.parse::<Shard>().unwrap_err();
        assert!(
            err("0/3").contains("shard 0 of 3 does not exist"),
            "{}",
            err("0/3")
        );
        assert!(
            err("4/3").contains("numbered 1 to 3 (e.g. 3/3)"),
            "{}",
            err("4/3")
        );
        assert!(
            err("a/b").contains("\"a\" is not a whole number"),
            "{}",
            err("a/b")
        );
        assert!(err("3").contains("no '/'"));
        assert!(err("1/0").contains("count is 0"));
    }

    #[test]
    fn slurm_array_tasks_map_to_shards() {
        assert_eq!(Shard::from_env(env(&[])), Ok(None));
        let s = Shard::from_env(env(&[
            ("SLURM_ARRAY_TASK_ID", "0"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ]));
        assert_eq!(s.unwrap().unwrap().0, Shard { index: 1, count: 4 });
        let s = Shard::from_env(env(&[
            ("SLURM_ARRAY_TASK_ID", "7"),
            ("SLURM_ARRAY_TASK_MIN", "1"),
            ("SLURM_ARRAY_TASK_STEP", "2"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ]));
        assert_eq!(s.unwrap().unwrap().0, Shard { index: 4, count: 4 });
        let e = Shard::from_env(env(&[("SLURM_ARRAY_TASK_ID", "9")])).unwrap_err();
        assert!(e.contains("SLURM_ARRAY_TASK_COUNT is not"), "{e}");
        let e = Shard::from_env(env(&[
            ("SLURM_ARRAY_TASK_ID", "9"),
            ("SLURM_ARRAY_TASK_COUNT", "4"),
        ]))
        .unwrap_err();
        assert!(e.contains("not task 1 to 4"), "{e}");
        let g = Shard::from_env(env(&[
            ("GRANULAR_SHARD", "2/5"),
            ("SLURM_ARRAY_TASK_ID", "0"),
        ]));
        assert_eq!(g.unwrap().unwrap().0, Shard { index: 2, count: 5 });
        assert!(Shard::from_env(env(&[("GRANULAR_SHARD", "6/5")])).is_err());
    }
}

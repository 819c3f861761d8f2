//! `--shard I/N`: a deterministic split of a list (jobs, or samples) into N parts, so that an
//! external scheduler (Slurm job arrays, Kubernetes Indexed Jobs, GNU parallel) can run part I
//! on one machine without any coordinator.

use std::str::FromStr;

/// Part `index` (from 0) of `count` parts.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Shard {
    /// Which part, `0 ≤ index < count`.
    pub index: u32,
    /// How many parts.
    pub count: u32,
}

impl Shard {
    /// The whole list as one part.
    pub const ALL: Shard = Shard { index: 0, count: 1 };

    /// Whether the item at `position` of the list belongs to this part: the items whose
    /// position ≡ index (mod count). Round-robin keeps neighbouring jobs (often of similar
    /// cost, e.g. consecutive frames) on different machines, which balances the parts.
    pub fn takes(&self, position: usize) -> bool {
        position % self.count as usize == self.index as usize
    }
}

impl FromStr for Shard {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let (i, n) = text
            .split_once('/')
            .ok_or_else(|| format!("'{text}' is not a shard: write I/N, e.g. 0/4"))?;
        let parse = |s: &str| {
            s.trim()
                .parse::<u32>()
                .map_err(|_| format!("'{s}' in shard '{text}' is not a whole number"))
        };
        let (index, count) = (parse(i)?, parse(n)?);
        if count == 0 || index >= count {
            return Err(format!(
                "shard '{text}': need 0 ≤ I < N (I counts from 0; Slurm's \
                 $SLURM_ARRAY_TASK_ID and Kubernetes' $JOB_COMPLETION_INDEX do)"
            ));
        }
        Ok(Shard { index, count })
    }
}

/// `glint batch --shard`: a fixed part `I/N`, or `auto` (the part the scheduler's
/// environment names; see [`from_environment`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ShardSpec {
    /// `I/N`.
    Fixed(Shard),
    /// `auto`.
    Auto,
}

impl FromStr for ShardSpec {
    type Err = String;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        if text.trim() == "auto" {
            Ok(ShardSpec::Auto)
        } else {
            text.parse().map(ShardSpec::Fixed).map_err(|e: String| {
                format!("{e}, or auto (the task index of a Slurm array or Kubernetes Indexed Job)")
            })
        }
    }
}

/// The environment variable that gives the shard count of a Kubernetes Indexed Job (which
/// sets only the index) when `--shard-count` does not.
pub const SHARD_COUNT_VAR: &str = "GLINT_SHARD_COUNT";

/// The shard a scheduler's environment names, and a line saying which variables gave it.
///
/// - Slurm job arrays: `SLURM_ARRAY_TASK_ID`, with `SLURM_ARRAY_TASK_MIN` (default 0) and
///   `SLURM_ARRAY_TASK_STEP` (default 1): index = (ID − MIN) / STEP; count =
///   `SLURM_ARRAY_TASK_COUNT`, or (MAX − MIN) / STEP + 1 from `SLURM_ARRAY_TASK_MAX` when COUNT
///   is absent. So `--array=1-16` and `--array=0-30:2` both give shards 0…15 of 16. An array
///   given as a list of unevenly spaced ids (`--array=1,5,9,10`) cannot be mapped to shards
///   and is refused.
/// - Kubernetes Indexed Jobs: `JOB_COMPLETION_INDEX` (from 0) as the index; the count from
///   `count` (`--shard-count N`), else [`SHARD_COUNT_VAR`].
///
/// Slurm wins when both are set. `env` reads a variable (`std::env::var` in the binary; a map
/// in tests).
pub fn from_environment(
    env: impl Fn(&str) -> Option<String>,
    count: Option<u32>,
) -> Result<(Shard, String), String> {
    let number = |name: &str| -> Result<Option<u64>, String> {
        match env(name) {
            None => Ok(None),
            Some(text) => text
                .trim()
                .parse()
                .map(Some)
                .map_err(|_| format!("--shard auto: {name}={text} is not a whole number")),
        }
    };
    let make = |index: u64, count: u64, from: String| -> Result<(Shard, String), String> {
        let fits = |v: u64| u32::try_from(v).ok();
        match (fits(index), fits(count)) {
            (Some(index), Some(count)) if count > 0 && index < count => Ok((
                Shard { index, count },
                format!("--shard auto: shard {index}/{count} from {from}"),
            )),
            _ => Err(format!(
                "--shard auto: {from} gives shard {index} of {count}, which does not exist \
                 (need 0 ≤ index < count); check the array's range, or give --shard I/N"
            )),
        }
    };
    if let Some(id) = number("SLURM_ARRAY_TASK_ID")? {
        let min = number("SLURM_ARRAY_TASK_MIN")?;
        let step = number("SLURM_ARRAY_TASK_STEP")?.unwrap_or(1).max(1);
        let base = min.unwrap_or(0);
        let mut from = format!("SLURM_ARRAY_TASK_ID={id}");
        if let Some(min) = min {
            from += &format!(", SLURM_ARRAY_TASK_MIN={min}");
        }
        if step != 1 {
            from += &format!(", SLURM_ARRAY_TASK_STEP={step}");
        }
        let offset = id
            .checked_sub(base)
            .filter(|o| o % step == 0)
            .ok_or_else(|| {
                format!(
                    "--shard auto: {from} is not on the array's grid MIN + k·STEP; an array of \
                 unevenly spaced ids cannot be split into shards: use --array=A-B[:S] or \
                 --shard I/N"
                )
            })?;
        let count = match (
            number("SLURM_ARRAY_TASK_COUNT")?,
            number("SLURM_ARRAY_TASK_MAX")?,
        ) {
            (Some(count), _) => {
                from += &format!(", SLURM_ARRAY_TASK_COUNT={count}");
                count
            }
            (None, Some(max)) => {
                from += &format!(", SLURM_ARRAY_TASK_MAX={max}");
                max.saturating_sub(base) / step + 1
            }
            (None, None) => {
                return Err(format!(
                    "--shard auto: {from} is set but neither SLURM_ARRAY_TASK_COUNT nor \
                     SLURM_ARRAY_TASK_MAX is, so the shard count is unknown; give --shard I/N"
                ));
            }
        };
        return make(offset / step, count, from);
    }
    if let Some(index) = number("JOB_COMPLETION_INDEX")? {
        let (count, from) = match (count, number(SHARD_COUNT_VAR)?) {
            (Some(n), _) => (
                n as u64,
                format!("JOB_COMPLETION_INDEX={index}, --shard-count {n}"),
            ),
            (None, Some(n)) => (
                n,
                format!("JOB_COMPLETION_INDEX={index}, {SHARD_COUNT_VAR}={n}"),
            ),
            (None, None) => {
                return Err(format!(
                    "--shard auto: JOB_COMPLETION_INDEX={index} is set, but not the number of \
                     shards: pass --shard-count N (the Job's completions) or set \
                     {SHARD_COUNT_VAR}"
                ));
            }
        };
        return make(index, count, from);
    }
    Err(
        "--shard auto found no task index: it reads SLURM_ARRAY_TASK_ID (Slurm job arrays) or \
         JOB_COMPLETION_INDEX (Kubernetes Indexed Jobs), and neither is set; outside such a \
         scheduler give --shard I/N"
            .into(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parses_and_rejects() {
        assert_eq!("2/5".parse(), Ok(Shard { index: 2, count: 5 }));
        assert!("5/5".parse::<Shard>().is_err());
        assert!("1/0".parse::<Shard>().is_err());
        assert!("1".parse::<Shard>().is_err());
        assert!("-1/3".parse::<Shard>().is_err());
    }

    #[test]
    fn parts_cover_every_position_once() {
        for count in 1..7 {
            for position in 0..50 {
                let owners = (0..count)
                    .filter(|&index| Shard { index, count }.takes(position))
                    .count();
                assert_eq!(owners, 1, "position {position} of {count} shards");
            }
        }
    }

    fn env<'a>(vars: &'a [(&'a str, &'a str)]) -> impl Fn(&str) -> Option<String> + 'a {
        move |name| {
            vars.iter()
                .find(|(k, _)| *k == name)
                .map(|(_, v)| v.to_string())
        }
    }

    #[test]
    fn auto_reads_slurm_and_kubernetes_indices() {
        let shard = |vars: &[(&str, &str)], count| from_environment(env(vars), count);
        let s = |index, count| Shard { index, count };
        let (got, line) = shard(
            &[
                ("SLURM_ARRAY_TASK_ID", "3"),
                ("SLURM_ARRAY_TASK_COUNT", "8"),
            ],
            None,
        )
        .unwrap();
        assert_eq!(got, s(3, 8));
        assert!(line.contains("SLURM_ARRAY_TASK_ID=3"), "{line}");
        // --array=1-16: ids 1…16 are shards 0…15.
        let one_based = [
            ("SLURM_ARRAY_TASK_ID", "16"),
            ("SLURM_ARRAY_TASK_MIN", "1"),
            ("SLURM_ARRAY_TASK_MAX", "16"),
        ];
        assert_eq!(shard(&one_based, None).unwrap().0, s(15, 16));
        // --array=0-30:2.
        let stepped = [
            ("SLURM_ARRAY_TASK_ID", "6"),
            ("SLURM_ARRAY_TASK_MIN", "0"),
            ("SLURM_ARRAY_TASK_MAX", "30"),
            ("SLURM_ARRAY_TASK_STEP", "2"),
        ];
        assert_eq!(shard(&stepped, None).unwrap().0, s(3, 16));
        let k8s = [("JOB_COMPLETION_INDEX", "2")];
        assert_eq!(shard(&k8s, Some(5)).unwrap().0, s(2, 5));
        let k8s_env = [("JOB_COMPLETION_INDEX", "2"), (SHARD_COUNT_VAR, "4")];
        let (got, line) = shard(&k8s_env, None).unwrap();
        assert_eq!(got, s(2, 4));
        assert!(line.contains(SHARD_COUNT_VAR), "{line}");
        for bad in [
            &[][..],
            &[("JOB_COMPLETION_INDEX", "2")][..],
            &[("JOB_COMPLETION_INDEX", "4"), (SHARD_COUNT_VAR, "4")][..],
            &[("SLURM_ARRAY_TASK_ID", "3")][..],
            &[
                ("SLURM_ARRAY_TASK_ID", "x"),
                ("SLURM_ARRAY_TASK_COUNT", "8"),
            ][..],
            &[
                ("SLURM_ARRAY_TASK_ID", "8"),
                ("SLURM_ARRAY_TASK_COUNT", "8"),
            ][..],
        ] {
            assert!(shard(bad, None).is_err(), "{bad:?} accepted");
        }
        assert_eq!("auto".parse(), Ok(ShardSpec::Auto));
        assert_eq!("1/2".parse(), Ok(ShardSpec::Fixed(s(1, 2))));
    }
}

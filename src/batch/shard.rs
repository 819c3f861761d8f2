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
}

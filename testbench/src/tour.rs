//! Transition tours: one input sequence that applies every input in every
//! reachable state of a model, so an HDL block can be driven through all
//! reachable (state, input) pairs while it is compared with the model every
//! clock.
//!
//! The states are enumerated from the model by breadth-first search; the
//! tour then walks the graph, taking an unused input where the current state
//! has one, and otherwise the shortest path to the nearest state that does.

use std::collections::{BTreeMap, BTreeSet, VecDeque};

/// The reachable graph of a model: states, and for each state the successor
/// under each input (by index into `inputs`).
pub struct Graph<S> {
    pub states: Vec<S>,
    pub next: Vec<Vec<usize>>,
}

impl<S> Graph<S> {
    /// Number of (state, input) pairs: the cases an exhaustive check covers.
    pub fn pairs(&self) -> usize {
        self.next.iter().map(|n| n.len()).sum()
    }
}

/// Enumerates every state reachable from `init` under `inputs`, stopping
/// with `Err` past `limit` states.
pub fn explore<S: Clone + Ord, I>(
    init: S,
    inputs: &[I],
    step: impl Fn(&S, &I) -> S,
    limit: usize,
) -> Result<Graph<S>, String> {
    let mut index: BTreeMap<S, usize> = BTreeMap::new();
    let mut states = vec![init.clone()];
    index.insert(init, 0);
    let mut next: Vec<Vec<usize>> = Vec::new();
    let mut i = 0;
    while i < states.len() {
        let mut row = Vec::with_capacity(inputs.len());
        for inp in inputs {
            let s = step(&states[i], inp);
            let id = match index.get(&s) {
                Some(&id) => id,
                None => {
                    if states.len() >= limit {
                        return Err(format!("more than {limit} reachable states"));
                    }
                    states.push(s.clone());
                    index.insert(s, states.len() - 1);
                    states.len() - 1
                }
            };
            row.push(id);
        }
        next.push(row);
        i += 1;
    }
    Ok(Graph { states, next })
}

/// A tour from state 0: the input indices to apply, in order. Every
/// (state, input) pair appears at least once.
pub fn tour<S>(g: &Graph<S>) -> Vec<usize> {
    let n = g.states.len();
    let mut unused: Vec<BTreeSet<usize>> = g.next.iter().map(|r| (0..r.len()).collect()).collect();
    let mut remaining = g.pairs();
    let mut out = Vec::with_capacity(remaining * 2);
    let mut at = 0;
    while remaining > 0 {
        // Prefer an unused input whose successor still has unused inputs:
        // it keeps the walk out of exhausted regions and shortens the tour.
        let pick = unused[at]
            .iter()
            .copied()
            .max_by_key(|&i| (unused[g.next[at][i]].len(), std::cmp::Reverse(i)));
        if let Some(inp) = pick {
            unused[at].remove(&inp);
            remaining -= 1;
            out.push(inp);
            at = g.next[at][inp];
            continue;
        }
        // Shortest path to a state with an unused input.
        let mut prev: Vec<Option<(usize, usize)>> = vec![None; n];
        let mut seen = vec![false; n];
        seen[at] = true;
        let mut q = VecDeque::from([at]);
        let mut target = None;
        while let Some(s) = q.pop_front() {
            if !unused[s].is_empty() {
                target = Some(s);
                break;
            }
            for (inp, &t) in g.next[s].iter().enumerate() {
                if !seen[t] {
                    seen[t] = true;
                    prev[t] = Some((s, inp));
                    q.push_back(t);
                }
            }
        }
        // Pairs that cannot be reached from here stay uncovered; the
        // check's coverage count then falls short and it fails.
        let Some(target) = target else { break };
        let mut path = Vec::new();
        let mut s = target;
        while s != at {
            let (p, inp) = prev[s].unwrap();
            path.push(inp);
            s = p;
        }
        path.reverse();
        for inp in path {
            // Walking over used pairs; mark them anyway (they were used).
            out.push(inp);
            at = g.next[at][inp];
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tour_covers_every_pair_of_a_counter_with_reset() {
        // A 3-bit counter with inputs {hold, inc, reset}.
        let g = explore(
            0u8,
            &[0u8, 1, 2],
            |s, i| match i {
                0 => *s,
                1 => (s + 1) % 8,
                _ => 0,
            },
            100,
        )
        .unwrap();
        assert_eq!(g.states.len(), 8);
        assert_eq!(g.pairs(), 24);
        let t = tour(&g);
        let mut covered = BTreeSet::new();
        let mut at = 0;
        for &i in &t {
            covered.insert((at, i));
            at = g.next[at][i];
        }
        assert_eq!(covered.len(), 24);
    }
}

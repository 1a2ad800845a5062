//! Near names, for did-you-mean hints: an unknown function, property, `--set` name or `doc`
//! topic is answered with the closest existing one.

/// The Levenshtein distance between `a` and `b` (in characters), for did-you-mean hints.
#[must_use]
pub fn edit_distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut diag = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let next = (diag + usize::from(ca != *cb)).min(row[j] + 1).min(row[j + 1] + 1);
            diag = row[j + 1];
            row[j + 1] = next;
        }
    }
    row[b.len()]
}

/// The name among `names` closest to `name` by [`edit_distance`], if close enough to be a
/// likely typo: at most 2 edits, or a third of the longer name's length.
#[must_use]
pub fn did_you_mean<'a>(name: &str, names: impl IntoIterator<Item = &'a str>) -> Option<&'a str> {
    names
        .into_iter()
        .map(|n| (edit_distance(name, n), n))
        .filter(|(d, n)| *d <= (name.chars().count().max(n.chars().count()) / 3).max(2))
        .min_by_key(|(d, _)| *d)
        .map(|(_, n)| n)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn did_you_mean_finds_the_closest_name_within_a_few_edits() {
        assert_eq!(edit_distance("leg_height", "legs_height"), 1);
        assert_eq!(edit_distance("", "abc"), 3);
        assert_eq!(edit_distance("kitten", "sitting"), 3);
        let names = ["legs_height", "width", "seed"];
        assert_eq!(did_you_mean("leg_height", names), Some("legs_height"));
        assert_eq!(did_you_mean("sed", names), Some("seed"));
        assert_eq!(did_you_mean("colour", names), None);
    }
}

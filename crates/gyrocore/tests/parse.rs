//! The core's parsers of the binding's string arguments: every name the binding passes through
//! parses, anything else is an error naming the argument.

use gyrocore::allan::{TauSpec, Taus};

#[test]
fn taus_parse_specs_explicit_values_and_rejects_unknown_names() {
    assert_eq!(
        Taus::parse("octave", 3, None).unwrap(),
        Taus::Spec(TauSpec::Octave)
    );
    assert_eq!(
        Taus::parse("decade", 3, None).unwrap(),
        Taus::Spec(TauSpec::Decade)
    );
    assert_eq!(
        Taus::parse("all", 3, None).unwrap(),
        Taus::Spec(TauSpec::All)
    );
    assert_eq!(
        Taus::parse("log", 7, None).unwrap(),
        Taus::Spec(TauSpec::Log { per_decade: 7 })
    );
    // Explicit values win over the specification string.
    assert_eq!(
        Taus::parse("octave", 3, Some(vec![0.1, 1.0])).unwrap(),
        Taus::Explicit(vec![0.1, 1.0])
    );
    let err = Taus::parse("weekly", 3, None).unwrap_err().to_string();
    assert!(err.contains("taus") && err.contains("weekly"), "{err}");
}

use super::*;
use std::collections::HashSet;

#[test]
fn de0_nano_headers_are_the_first_88_pins() {
    assert_eq!(DE0_NANO[DE0_NANO_HEADER_PINS - 1].0, "PIN_G15");
    assert_eq!(DE0_NANO[DE0_NANO_HEADER_PINS].0, "PIN_M1");
}

#[test]
fn pools_have_no_duplicates_and_exclude_the_clock() {
    for b in BOARDS {
        let mut seen = HashSet::new();
        for (p, _) in b.pool {
            assert!(seen.insert(*p), "{}: {p} twice", b.name);
            assert_ne!(*p, b.clock_pin, "{}: clock pin in the pool", b.name);
        }
    }
}

#[test]
fn default_config_fits_the_ice40_and_ecp5_boards_and_two_axes_every_board() {
    // The DE0-Nano's 100 pins hold two axes without the general-purpose
    // I/O, not the default's four with it.
    let two = Config::default()
        .with_axes(2)
        .and_then(|c| c.with_gpio_pins(0, 0))
        .unwrap();
    for (config, boards) in [(Config::default(), &BOARDS[..2]), (two, &BOARDS[..])] {
        fits(&config, boards);
    }
    assert_eq!(files(&Config::default()).len(), 2);
    assert_eq!(files(&two).len(), 4);
    assert!(assign(&CYCLONE4_DE0_NANO, &board::ports(&Config::default())).is_err());
}

fn fits(config: &Config, boards: &[&Board]) {
    let ports = board::ports(config);
    for b in boards {
        let a = assign(b, &ports).unwrap();
        let bits: usize = ports.iter().map(|p| p.bits().len()).sum();
        assert_eq!(a.len(), bits, "{}", b.name);
        let pins: HashSet<_> = a.iter().map(|a| a.pin).collect();
        assert_eq!(pins.len(), a.len(), "{}: a pin used twice", b.name);
    }
}

//! Distance travelled, as ZigZag and LegRun count it (behaviors-more.md §8.3, §9): after
//! a reset the first position only starts the count; while paused, moves are not added
//! but the last position still follows ownship.

#[derive(Clone, Debug, Default, PartialEq)]
pub struct Odometer {
    last: Option<(f64, f64)>,
    total: f64,
    paused: bool,
}

impl Odometer {
    pub fn update(&mut self, x: f64, y: f64) {
        if let Some((px, py)) = self.last {
            if !self.paused {
                self.total += (x - px).hypot(y - py);
            }
        }
        self.last = Some((x, y));
    }

    pub fn reset(&mut self) {
        self.last = None;
        self.total = 0.0;
    }

    pub fn pause(&mut self, paused: bool) {
        self.paused = paused;
    }

    pub fn total(&self) -> f64 {
        self.total
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn counts_moves_after_the_first_position() {
        let mut o = Odometer::default();
        o.update(10.0, 10.0);
        assert_eq!(o.total(), 0.0);
        o.update(13.0, 14.0);
        assert_eq!(o.total(), 5.0);
        o.pause(true);
        o.update(13.0, 24.0);
        assert_eq!(o.total(), 5.0);
        o.pause(false);
        o.update(13.0, 25.0);
        assert_eq!(o.total(), 6.0);
        o.reset();
        o.update(0.0, 0.0);
        assert_eq!(o.total(), 0.0);
    }
}

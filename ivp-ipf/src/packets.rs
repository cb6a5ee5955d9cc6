//! BHV_IPF packets (ivp-solver.md §9.2): the whole-function string split for posting,
//! and what each behavior keeps of its last function's text.

use super::{
    encode_context_into, encode_pieces_into, encode_shape_into, encode_source_into, IpfSource,
};
use ivp::IvpFunction;

/// Smallest packet body. The spec's `2000 - header` goes to 0 and below for behavior
/// names of 1950+ characters (one packet per character, thousands per iteration); names
/// under 1450 characters never reach this floor, so real missions are split as specified.
const MIN_BODY: usize = 500;

/// The BHV_IPF packets of one whole-function string (spec §9.2, packet size 2000),
/// measured once and written one at a time into caller-owned strings. The string may
/// come in parts, one after the other, so kept text need not be copied to be sent.
#[derive(Clone, Copy, Debug)]
pub struct Packets<'a> {
    id: &'a str,
    parts: [&'a str; 3],
    /// Characters of body per packet.
    body: usize,
    count: usize,
    /// Bytes are characters (the usual case): bodies are byte slices.
    ascii: bool,
}

impl<'a> Packets<'a> {
    pub fn new(id: &'a str, whole: &'a str) -> Self {
        Self::of_parts(id, [whole, "", ""])
    }

    /// The packets of the string made of `parts` one after the other.
    pub fn of_parts(id: &'a str, parts: [&'a str; 3]) -> Self {
        let ascii = parts.iter().all(|p| p.is_ascii());
        Self::with_ascii(id, parts, ascii, chars(id, id.is_ascii()))
    }

    /// [`Packets::of_parts`] told whether the parts are ASCII (kept text is scanned
    /// once, when it is formatted, not at every sending) and the id's characters.
    fn with_ascii(id: &'a str, parts: [&'a str; 3], ascii: bool, id_chars: usize) -> Self {
        let header = id_chars + 50;
        let body = 2000usize.saturating_sub(header).max(MIN_BODY);
        let chars: usize = if ascii {
            parts.iter().map(|p| p.len()).sum()
        } else {
            parts.iter().map(|p| p.chars().count()).sum()
        };
        Packets {
            id,
            parts,
            body,
            count: chars / body + 1,
            ascii,
        }
    }

    /// How many packets.
    pub fn count(&self) -> usize {
        self.count
    }

    /// Packet `k` (1-based) written into `out` (cleared first; its allocation is kept).
    pub fn write(&self, k: usize, out: &mut String) {
        out.clear();
        out.push_str("P,");
        out.push_str(self.id);
        if (self.count, k) == (1, 1) {
            // The usual single packet: its numbers without formatting them.
            out.push_str(",1,1,");
        } else {
            out.push(',');
            out.push_str(itoa::Buffer::new().format(self.count));
            out.push(',');
            out.push_str(itoa::Buffer::new().format(k));
            out.push(',');
        }
        let first = k.saturating_sub(1) * self.body;
        if self.ascii {
            // The byte range [first, first + body) of the parts laid end to end.
            let (mut start, mut end) = (first, first + self.body);
            for part in self.parts {
                let n = part.len();
                if start < n && end > start {
                    out.push_str(&part[start..end.min(n)]);
                }
                start = start.saturating_sub(n);
                end = end.saturating_sub(n);
            }
        } else {
            let [a, b, c] = self.parts;
            let whole = a.chars().chain(b.chars()).chain(c.chars());
            out.extend(whole.skip(first).take(self.body));
        }
    }
}

/// One behavior's BHV_IPF posting as the helm writes it every iteration: the strings
/// are kept, so once they have grown to the function's size nothing is allocated.
#[derive(Debug, Default)]
pub struct IpfWriter {
    whole: String,
    id: String,
}

impl IpfWriter {
    /// `f` as behavior `name`'s function of iteration `iter` (packet id `name^iter`),
    /// ready to be written packet by packet.
    pub fn packets(&mut self, f: &IvpFunction, name: &str, iter: u64) -> Packets<'_> {
        self.source_packets(f.into(), name, iter)
    }

    /// [`IpfWriter::packets`] from borrowed parts.
    pub fn source_packets(&mut self, f: IpfSource<'_>, name: &str, iter: u64) -> Packets<'_> {
        encode_source_into(f, &mut self.whole);
        self.set_id(name, itoa::Buffer::new().format(iter));
        Packets::new(&self.id, &self.whole)
    }

    /// [`IpfWriter::source_packets`] with the text after the context taken from `kept`
    /// where the numbers it shows are the ones it last formatted (bit for bit), and
    /// formatted into it otherwise.
    pub fn kept_packets<'s>(
        &'s mut self,
        f: IpfSource<'_>,
        kept: &'s mut KeptIpf,
        name: &str,
        iter: u64,
    ) -> Packets<'s> {
        encode_context_into(&f, &mut self.whole);
        self.set_id(name, itoa::Buffer::new().format(iter));
        let (whole_ascii, id_ascii) = (self.whole.is_ascii(), name.is_ascii());
        kept.keep(&f);
        self.kept_rest(kept, whole_ascii, id_ascii)
    }

    /// [`IpfWriter::kept_packets`] with the helm's context, `iter:name`, written here
    /// straight into the text (`f.context` is not read): the helm need not build it.
    pub fn helm_packets<'s>(
        &'s mut self,
        f: IpfSource<'_>,
        kept: &'s mut KeptIpf,
        name: &str,
        iter: u64,
    ) -> Packets<'s> {
        kept.keep(&f);
        self.kept_helm_packets(kept, name, iter)
    }

    /// [`IpfWriter::helm_packets`] of the function `kept` was last given
    /// ([`KeptIpf::keep`]), nothing formatted again: the helm formats a function in its
    /// decision step (before the solve changes it) and splits its text into packets when
    /// it publishes the behavior's messages (helm.md §8.3), as the real helm does.
    pub fn kept_helm_packets<'s>(
        &'s mut self,
        kept: &'s KeptIpf,
        name: &str,
        iter: u64,
    ) -> Packets<'s> {
        let mut digits = itoa::Buffer::new();
        let iter_text = digits.format(iter);
        // The context and the id are digits, punctuation and the name: ASCII with it.
        let ascii = name.is_ascii();
        // `H,<characters of the context>,<context>,` as `encode_context_into` writes it.
        let w = &mut self.whole;
        w.clear();
        w.push_str("H,");
        w.push_str(itoa::Buffer::new().format(iter_text.len() + 1 + chars(name, ascii)));
        w.push(',');
        w.push_str(iter_text);
        w.push(':');
        w.push_str(name);
        w.push(',');
        self.set_id(name, iter_text);
        self.kept_rest(kept, ascii, ascii)
    }

    /// The packets once the context is in `whole` and the id set (told whether they
    /// are ASCII): the rest from `kept`.
    fn kept_rest<'s>(
        &'s self,
        kept: &'s KeptIpf,
        whole_ascii: bool,
        id_ascii: bool,
    ) -> Packets<'s> {
        // The pieces are numbers and commas only, ASCII by construction.
        debug_assert!(kept.pieces.is_ascii());
        let ascii = kept.shape_ascii && whole_ascii;
        let parts = [self.whole.as_str(), &kept.shape, &kept.pieces];
        Packets::with_ascii(&self.id, parts, ascii, chars(&self.id, id_ascii))
    }

    /// The packet id, `name^iter` (`iter` in digits).
    fn set_id(&mut self, name: &str, iter: &str) {
        self.id.clear();
        self.id.push_str(name);
        self.id.push('^');
        self.id.push_str(iter);
    }
}

/// Characters of `text`: its bytes when ASCII (as a behavior's name is), told so by
/// the caller, else counted.
fn chars(text: &str, ascii: bool) -> usize {
    if ascii {
        text.len()
    } else {
        text.chars().count()
    }
}

/// One behavior's last function as BHV_IPF shows it after the context (which holds
/// the iteration), with the numbers that text was made of. A function that is the same
/// from one iteration to the next (a constant depth, a held speed) is formatted once,
/// and a changing function's domain and weight once while they hold: comparing numbers
/// costs a fraction of printing them.
#[derive(Debug, Default)]
pub struct KeptIpf {
    /// The text from the dimension to `F`, and what it shows.
    shape: String,
    shape_ascii: bool,
    count: usize,
    pwt: u64,
    gelbox: Vec<u32>,
    domain: Option<ivp::Domain>,
    /// The pieces' text, and what it shows (weights compared bit for bit: 0.0 and -0.0
    /// apart).
    pieces: String,
    pieces_valid: bool,
    dim: usize,
    bounds: Vec<i32>,
    weights: Vec<f64>,
    /// Iterations in a row the pieces changed.
    pub(crate) changed: u32,
}

impl KeptIpf {
    /// The text of `f` after its context, formatted where the numbers it shows changed
    /// since the last function kept.
    pub fn keep(&mut self, f: &IpfSource<'_>) {
        let dim = f.domain.size();
        let count = f.weights.len() / (dim + 1);
        let same_domain = self
            .domain
            .as_ref()
            .is_some_and(|d| same_domain(d, f.domain));
        // The domain is kept from the first function on.
        let shape_kept = same_domain
            && self.count == count
            && self.pwt == f.pwt.to_bits()
            && self.gelbox == f.gelbox;
        if !shape_kept {
            self.shape.clear();
            encode_shape_into(f, &mut self.shape);
            self.shape_ascii = self.shape.is_ascii();
            if !same_domain {
                self.domain = Some(f.domain.clone());
            }
            (self.count, self.pwt) = (count, f.pwt.to_bits());
            self.gelbox.clear();
            self.gelbox.extend_from_slice(f.gelbox);
        }
        let pieces_kept = self.pieces_valid
            && self.dim == dim
            && self.bounds == f.bounds
            && self.weights.len() == f.weights.len()
            && (self.weights.iter().zip(f.weights)).all(|(a, b)| a.to_bits() == b.to_bits());
        if pieces_kept {
            self.changed = 0;
            return;
        }
        self.pieces.clear();
        encode_pieces_into(f, &mut self.pieces);
        self.changed = self.changed.saturating_add(1);
        // The numbers of a function that changes every iteration (one that follows a
        // contact: thousands of pieces) are copied only now and then, to notice when
        // it settles.
        self.pieces_valid = self.changed <= 2 || self.changed.is_multiple_of(8);
        if self.pieces_valid {
            self.dim = dim;
            self.bounds.clear();
            self.bounds.extend_from_slice(f.bounds);
            self.weights.clear();
            self.weights.extend_from_slice(f.weights);
        }
    }
}

/// The same domain text: names, points, and the bounds bit for bit.
fn same_domain(a: &ivp::Domain, b: &ivp::Domain) -> bool {
    a.size() == b.size()
        && a.vars().iter().zip(b.vars()).all(|(x, y)| {
            x.name == y.name
                && x.points == y.points
                && x.low.to_bits() == y.low.to_bits()
                && x.high.to_bits() == y.high.to_bits()
        })
}

/// Split a whole-function string into BHV_IPF packets (spec §9.2, packet size 2000).
pub fn ipf_packets(id: &str, whole: &str) -> Vec<String> {
    let packets = Packets::new(id, whole);
    (1..=packets.count())
        .map(|k| {
            let mut p = String::new();
            packets.write(k, &mut p);
            p
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use ivp::{Domain, IvpFunction};

    /// The helm's path (context written by the writer) gives the packets of the
    /// context passed in, for ASCII and other names, short and long (several packets),
    /// as the function changes and holds.
    #[test]
    fn helm_packets_equal_kept_packets_with_the_context_passed_in() {
        let d = Domain::parse("course:0:359:360").unwrap();
        let names = ["a", "wpt_survey", "tête_à_tête", &"long".repeat(300)];
        let (mut a, mut b) = (String::new(), String::new());
        for (case, name) in names.iter().enumerate() {
            let (mut kept_a, mut kept_b) = (KeptIpf::default(), KeptIpf::default());
            let (mut wa, mut wb) = (IpfWriter::default(), IpfWriter::default());
            for iter in [0u64, 1, 9, 10, 99, 12345, 12345, u64::MAX] {
                let k = (iter % 7) as i32 + case as i32;
                let pieces: Vec<_> = (0..40i32)
                    .map(|i| {
                        (
                            vec![(9 * i, 9 * i + 8)],
                            vec![0.5 * f64::from(i), f64::from(k)],
                        )
                    })
                    .collect();
                let mut f = IvpFunction::from_pieces(d.clone(), &pieces).unwrap();
                f.set_context(&format!("{iter}:{name}"));
                let want = wa.kept_packets((&f).into(), &mut kept_a, name, iter);
                let src = IpfSource {
                    context: "",
                    ..(&f).into()
                };
                let got = wb.helm_packets(src, &mut kept_b, name, iter);
                assert_eq!(got.count(), want.count(), "{name} {iter}");
                for p in 1..=want.count() {
                    want.write(p, &mut a);
                    got.write(p, &mut b);
                    assert_eq!(a, b, "{name} {iter} packet {p}");
                }
            }
        }
    }

    /// The helm's deferred path: functions kept in the decision step ([`KeptIpf::keep`]),
    /// packets written later ([`IpfWriter::kept_helm_packets`]) by one writer shared by
    /// the behaviors, in any order: each behavior's packets as [`IpfWriter::helm_packets`]
    /// gives them at once, and again unchanged when asked twice.
    #[test]
    fn kept_helm_packets_written_later_equal_helm_packets() {
        let d = Domain::parse("course:0:359:360,speed:0:4:41").unwrap();
        let names = ["avd_abe", "tête", &"n".repeat(1990)];
        let (mut a, mut b) = (String::new(), String::new());
        let mut shared = IpfWriter::default();
        let mut kept: Vec<KeptIpf> = names.iter().map(|_| KeptIpf::default()).collect();
        for iter in [1u64, 2, 3, 40, 41] {
            let fs: Vec<IvpFunction> = (0..names.len())
                .map(|n| {
                    let pieces: Vec<_> = (0..(60 * (n as i32 + 1)))
                        .map(|i| {
                            let c = (6 * i) % 360;
                            let w = f64::from(i) * 0.37 - f64::from(iter as u32) * 1.1;
                            (vec![(c, c + 5), (0, 40)], vec![w, -0.5, 100.0 - w])
                        })
                        .collect();
                    IvpFunction::from_pieces(d.clone(), &pieces).unwrap()
                })
                .collect();
            for (f, k) in fs.iter().zip(&mut kept) {
                k.keep(&IpfSource {
                    context: "",
                    ..f.into()
                });
            }
            for n in [2, 0, 1, 0] {
                let mut alone = (IpfWriter::default(), KeptIpf::default());
                let src = IpfSource {
                    context: "",
                    ..(&fs[n]).into()
                };
                let want = alone.0.helm_packets(src, &mut alone.1, names[n], iter);
                let got = shared.kept_helm_packets(&kept[n], names[n], iter);
                assert_eq!(got.count(), want.count(), "{n} {iter}");
                for p in 1..=want.count() {
                    want.write(p, &mut a);
                    got.write(p, &mut b);
                    assert_eq!(a, b, "{n} {iter} packet {p}");
                }
            }
        }
    }
}

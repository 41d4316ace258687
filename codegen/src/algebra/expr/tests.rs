//! Tests of the arena: interning, constants, sums' kept terms, hash collisions.

use super::*;

/// A constant made again, by `number` or inside a constructor, is the node made first
/// (also one made by a plain intern before the constant map saw it), and each call
/// counts as work.
#[test]
fn a_constant_is_one_node_however_made() {
    let mut a = Arena::new();
    let direct = a.intern(Node::Num(Number::int(3)));
    let work = a.effort().work;
    assert_eq!(a.int(3), direct);
    assert_eq!(a.int(3), direct);
    assert_eq!(a.effort().work, work + 2);
    let half = a.rational(1, 2).unwrap();
    let x = a.symbol("x", SymbolKind::Free);
    let hx = a.mul2(half, x);
    assert_eq!(
        a.split_coefficient(hx),
        (Number::rational(1, 2).unwrap(), Some(x))
    );
    assert_eq!(a.number(Number::rational(2, 4).unwrap()), half);
    let f = a.float(0.25).unwrap();
    assert_ne!(
        f,
        a.rational(1, 4).unwrap(),
        "0.25 and 1/4 are different constants"
    );
    assert_eq!(a.float(0.25).unwrap(), f);
    let before = a.len();
    a.int(3);
    a.float(0.25).unwrap();
    assert_eq!(a.len(), before, "no node made again");
}

/// A sum keeps each term that nothing merged into as that very node, and rebuilds the
/// others: like terms collect, and a lowering's c * (a + b) kept as one product is
/// scaled out again (c distributed over the inner sum), never kept as the product.
#[test]
fn a_sum_keeps_unmerged_terms_and_distributes_a_scaled_sum() {
    let mut a = Arena::new();
    let [x, y, z] = ["x", "y", "z"].map(|n| a.symbol(n, SymbolKind::Free));
    let half = a.rational(1, 2).unwrap();
    let hx = a.mul2(half, x);
    let three = a.int(3);
    let yz = a.mul(&[three, y, z]);
    let s = a.add(&[hx, yz, hx]);
    assert_eq!(s, a.add(&[x, yz]), "1/2 x + 1/2 x collect to x");
    let two = a.int(2);
    let kept_terms = a.add(&[hx, yz]);
    assert_eq!(a.node(kept_terms), &Node::Add(Operands::from([hx, yz])));
    let xy = a.add2(x, y);
    let kept = a.scaled_sum(Number::int(2), xy);
    assert!(
        matches!(a.node(kept), Node::Mul(_)),
        "c * (a + b) as one product"
    );
    let sum = a.add2(kept, z);
    let (x2, y2) = (a.mul2(two, x), a.mul2(two, y));
    let distributed = a.add2(x2, y2);
    let Node::Add(terms) = a.node(sum) else {
        panic!("a sum");
    };
    assert!(terms.contains(&distributed) && !terms.contains(&kept));
}

/// A node whose hash an earlier, different node already holds (a 32-bit collision,
/// forced here by planting that hash on the earlier node) gets a node of its own, is
/// found again by value, and leaves the earlier node found by its hash.
#[test]
fn a_hash_collision_keeps_both_nodes_apart() {
    let mut a = Arena::new();
    let x = a.symbol("x", SymbolKind::Free);
    let y = a.symbol("y", SymbolKind::Free);
    let colliding = Node::Pow(x, y);
    let planted = a
        .intern
        .find_or_insert(node_hash(&colliding), x.0, |_| false);
    assert_eq!(planted, None);
    let before = a.len();
    let p = a.intern(colliding.clone());
    assert_eq!(p.index(), before, "a new node, not the planted one");
    assert_eq!(a.node(p), &colliding);
    assert_eq!(a.intern(colliding), p, "found again, by value");
    let x_node = a.node(x).clone();
    assert_eq!(a.intern(x_node), x);
    assert_eq!(a.len(), before + 1);
}

/// A named sum is one operand: a sum holding it is not flattened into it, a number scales
/// it with one product, like named terms collect, and its constant stays outside, so
/// constants still fold. A product, a symbol or a number is not named.
#[test]
fn a_named_sum_is_one_operand() {
    let mut a = Arena::new();
    let [x, y, z] = ["x", "y", "z"].map(|s| a.symbol(s, SymbolKind::Free));
    let xy = a.add2(x, y);
    let n = a.named(xy);
    assert_eq!(a.node(n), &Node::Named(xy));
    assert_eq!(a.named(n), n, "named once");
    let s = a.add2(n, z);
    assert!(
        matches!(a.node(s), Node::Add(ts) if ts.len() == 2),
        "not flattened"
    );
    let three = a.int(3);
    let scaled = a.mul2(three, n);
    assert!(
        matches!(a.node(scaled), Node::Mul(fs) if fs.len() == 2),
        "not distributed"
    );
    let twice = a.add2(n, n);
    let two = a.int(2);
    assert_eq!(twice, a.mul2(two, n));
    let minus = a.neg(n);
    let none = a.add2(n, minus);
    assert!(a.is_zero(none));
    // The constant of a named sum stays outside the name and folds with another.
    let one = a.int(1);
    let c = a.add(&[one, x, y]);
    let named = a.named(c);
    assert_eq!(named, a.add2(one, n));
    let four = a.int(4);
    let folded = a.add2(named, four);
    let five = a.int(5);
    assert_eq!(folded, a.add2(five, n));
    // A constant plus one term is not worth a name.
    let x1 = a.add2(one, x);
    assert_eq!(a.named(x1), x1);
    let p = a.mul2(x, y);
    assert_eq!(a.named(p), p);
    assert_eq!(a.named(x), x);
    assert_eq!(a.named(three), three);
}

/// Evaluation, differentiation and lowering see through a name: its value is its sum's,
/// d(named u)/dx = named du/dx, and a program computes it once, with no instruction of its
/// own.
#[test]
fn a_named_sum_evaluates_and_differentiates_as_its_sum() {
    use crate::algebra::diff::Differentiator;
    use crate::algebra::eval::eval;
    let mut a = Arena::new();
    let [x, y] = ["x", "y"].map(|s| a.symbol(s, SymbolKind::Free));
    let xs = a.as_symbol(x).unwrap();
    let x2 = a.mul2(x, x);
    let u = a.add2(x2, y);
    let n = a.named(u);
    let e = a.mul2(n, n);
    let env = |s: SymbolId| Some(if s == xs { 1.5 } else { -0.25 });
    let v = 1.5 * 1.5 - 0.25;
    assert_eq!(eval(&a, e, &env).unwrap(), v * v);
    let mut d = Differentiator::new();
    let de = d.diff(&mut a, e, xs).unwrap();
    // d(u^2)/dx = 2 u du/dx = 2 u (2 x).
    assert_eq!(eval(&a, de, &env).unwrap(), 2.0 * v * 3.0);
    let program =
        crate::program::cse::Program::new(&a, &[&crate::Matrix::column(vec![e])]).unwrap();
    // x*x, + y, then the square: three operations.
    assert_eq!(program.op_counts().total(), 3);
}

//! Unit tests of expressions, and of the keyword renaming.

use super::*;
use crate::span::Span;

#[test]
fn expressions_fold_constants() {
    assert_eq!(Expr::and([Expr::TRUE, Expr::TRUE]), Expr::TRUE);
    assert_eq!(Expr::or([Expr::FALSE]), Expr::FALSE);
    assert_eq!(Expr::and([Expr::FALSE, Expr::var(VarId(0))]), Expr::FALSE);
    let v = Expr::var(VarId(1));
    assert_eq!(
        Expr::negation(Expr::eq(v.clone(), Expr::int(2))),
        Expr::ne(v.clone(), Expr::int(2))
    );
    assert_eq!(Expr::within(&v, 3, 2), Expr::FALSE);
    assert_eq!(Expr::add([Expr::int(1), Expr::int(2)]), Expr::int(3));
    assert_eq!(
        Expr::ite(Expr::TRUE, Expr::int(4), Expr::int(5)),
        Expr::int(4)
    );
}

#[test]
fn negation_and_intervals() {
    for op in [
        CmpOp::Eq,
        CmpOp::Ne,
        CmpOp::Lt,
        CmpOp::Le,
        CmpOp::Gt,
        CmpOp::Ge,
    ] {
        assert_eq!(op.negate().negate(), op);
        for (a, b) in [(1, 2), (2, 2), (3, 2)] {
            assert_ne!(op.eval(a, b), op.negate().eval(a, b), "{op:?} {a} {b}");
        }
    }
    let v = Expr::var(VarId(0));
    assert_eq!(Expr::within(&v, 2, 2), Expr::eq(v.clone(), Expr::int(2)));
    assert!(matches!(Expr::within(&v, 1, 3), Expr::And(ref items) if items.len() == 2));
    assert_eq!(Expr::or([Expr::TRUE, v.clone()]), Expr::TRUE);
    assert_eq!(
        Expr::and([v.clone(), v.clone()]),
        v,
        "duplicates are dropped"
    );
}

#[test]
fn fresh_names_avoid_keywords_and_used_names() {
    let mut r = Renaming::default();
    r.used.insert("hurry".to_owned());
    assert_eq!(r.fresh("hurry"), "hurry_");
    assert_eq!(r.fresh("hurry"), "hurry__");
    assert_eq!(r.fresh("int"), "int_");
    assert_eq!(r.get("int"), "int__", "a renaming avoids fresh names too");
    assert_eq!(r.name("int"), "int__");
    assert_eq!(r.name("plain"), "plain");
}

#[test]
fn keywords_are_renamed_once_and_consistently() {
    let net = Network {
        name: "sync".to_owned(),
        unit_ns: 1,
        horizon: 1,
        clocks: Vec::new(),
        vars: vec![IntVar {
            name: "sync_".to_owned(),
            size: 1,
            min: 0,
            max: 1,
            init: 0,
            array: false,
            span: Span::default(),
            description: String::new(),
        }],
        events: Vec::new(),
        processes: Vec::new(),
        syncs: Vec::new(),
        labels: Vec::new(),
        services: Vec::new(),
        frozen: VarId(0),
        urgency: Expr::FALSE,
    };
    let mut r = Renaming::new(&net, &[]);
    assert_eq!(r.get("sync"), "sync__");
    assert_eq!(r.get("sync_"), "sync_");
    assert_eq!(r.renamed, vec![("sync".to_owned(), "sync__".to_owned())]);
}

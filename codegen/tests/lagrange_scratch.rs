use mechanism_codegen::*;
#[test]
fn show() {
    let mut model = closed_chain_model(3);
    let eqs = derive(&mut model).unwrap();
    println!("{}", equations_text(&model, &eqs));
    let cq = christoffel_coriolis_forces(&mut model, &eqs).unwrap();
    println!("{}", matrix_to_text(&model.arena, "Cq_chr", &cq));
    println!("{}", closed_chain_source(3));
}

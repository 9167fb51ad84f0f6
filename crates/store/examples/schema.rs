//! Prints the datasets of a scan file and of an atlas file from the tables that write them
//! (`cargo run -p squeal-store --example schema`).

fn main() {
    println!("scan files (squeal-basins/1):");
    print!("{}", squeal_store::schema::text());
    println!("atlas files (squeal-atlas/1):");
    print!("{}", squeal_store::schema::atlas_text());
}

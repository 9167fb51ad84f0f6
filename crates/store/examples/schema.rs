//! Prints the per-cell and per-map datasets of a scan file from the tables that write them
//! (`cargo run -p squeal-store --example schema`).

fn main() {
    print!("{}", squeal_store::schema::text());
}

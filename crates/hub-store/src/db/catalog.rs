//! The database's own catalogue: its tables and their rows, on either backend (what a backup
//! counts and checks, and what a patient's export and erasure walk).

use std::collections::BTreeMap;

use sqlx::Row;

use super::{Backend, Db};
use crate::error::HubError;

/// The database's own tables (not the migration bookkeeping, which the schema version states).
pub async fn table_names<'c, E>(conn: E, backend: Backend) -> Result<Vec<String>, HubError>
where
    E: sqlx::Executor<'c, Database = sqlx::Any>,
{
    let sql = match backend {
        Backend::Sqlite => {
            "SELECT name FROM sqlite_master WHERE type = 'table' \
             AND name NOT LIKE 'sqlite_%' AND name NOT LIKE '_sqlx%' ORDER BY name"
        }
        Backend::Postgres => {
            "SELECT CAST(table_name AS TEXT) FROM information_schema.tables \
             WHERE table_schema = 'public' AND table_type = 'BASE TABLE' \
             AND table_name NOT LIKE '_sqlx%' ORDER BY table_name"
        }
    };
    let rows = sqlx::query(sql)
        .fetch_all(conn)
        .await
        .map_err(HubError::db("listing the tables"))?;
    rows.iter()
        .map(|r| r.try_get::<String, _>(0))
        .collect::<Result<_, _>>()
        .map_err(HubError::db("listing the tables"))
}

/// The rows of `table` (a name from the catalogue).
pub async fn count_rows<'c, E>(conn: E, table: &str) -> Result<i64, HubError>
where
    E: sqlx::Executor<'c, Database = sqlx::Any>,
{
    // The name comes from the database's own catalogue, quoted as an identifier.
    let sql = format!("SELECT COUNT(*) FROM \"{}\"", table.replace('"', "\"\""));
    sqlx::query(sqlx::AssertSqlSafe(sql))
        .fetch_one(conn)
        .await
        .and_then(|r| r.try_get::<i64, _>(0))
        .map_err(HubError::db("counting rows"))
}

/// Every table's rows in `db`.
pub async fn row_counts(db: &Db) -> Result<BTreeMap<String, i64>, HubError> {
    let mut rows = BTreeMap::new();
    for table in table_names(db.pool(), db.backend()).await? {
        let n = count_rows(db.pool(), &table).await?;
        rows.insert(table, n);
    }
    Ok(rows)
}

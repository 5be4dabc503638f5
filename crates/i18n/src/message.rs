//! What the tests need to know of one message of a catalogue (the patient's or the console's):
//! its id, its file and the variables it uses, read from its Fluent pattern.

use fluent_syntax::ast;

/// What the tests need to know of one message.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct MessageInfo {
    /// `area-thing`, or `area-thing.attribute` for an attribute.
    pub id: String,
    /// The file it is in (`en/session.ftl`).
    pub file: String,
    /// The variables it uses (`$seconds` → `seconds`), sorted.
    pub variables: Vec<String>,
}

pub(crate) fn info(id: String, file: &str, pattern: &ast::Pattern<&str>) -> MessageInfo {
    let mut variables = Vec::new();
    collect_variables(pattern, &mut variables);
    variables.sort();
    variables.dedup();
    MessageInfo {
        id,
        file: file.to_string(),
        variables,
    }
}

fn collect_variables(pattern: &ast::Pattern<&str>, out: &mut Vec<String>) {
    for element in &pattern.elements {
        if let ast::PatternElement::Placeable { expression } = element {
            collect_in_expression(expression, out);
        }
    }
}

fn collect_in_expression(expression: &ast::Expression<&str>, out: &mut Vec<String>) {
    match expression {
        ast::Expression::Select { selector, variants } => {
            collect_in_inline(selector, out);
            for v in variants {
                collect_variables(&v.value, out);
            }
        }
        ast::Expression::Inline(inline) => collect_in_inline(inline, out),
    }
}

fn collect_in_inline(inline: &ast::InlineExpression<&str>, out: &mut Vec<String>) {
    match inline {
        ast::InlineExpression::VariableReference { id } => out.push(id.name.to_string()),
        ast::InlineExpression::FunctionReference { arguments, .. } => {
            for a in &arguments.positional {
                collect_in_inline(a, out);
            }
            for n in &arguments.named {
                collect_in_inline(&n.value, out);
            }
        }
        ast::InlineExpression::Placeable { expression } => collect_in_expression(expression, out),
        _ => {}
    }
}

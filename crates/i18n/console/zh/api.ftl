# 集线器的拒绝信息，以控制台的语言显示（crates/hub/console/api.js refusalWords）。

## 集线器的拒绝信息，以控制台的语言显示；集线器自己的说明（字段或对象）在有用时以英文附上。

api-error-400 = 集线器没有接受此内容。
api-error-401 = 未登录，或电子邮件或密码错误。
api-error-403 = 只有诊所管理员可以执行此操作。
api-error-404 = 未找到，可能已被删除。
api-error-409 = 这与集线器中保存的内容冲突。
api-error-413 = 内容太大，集线器无法接收。
api-error-415 = 集线器无法理解此请求。
api-error-422 = 已拒绝：超出允许的数值或安全范围。
api-error-429 = 尝试次数过多。请在 { $seconds } 秒后重试。
api-error-503 = 集线器正忙。请在 { $seconds } 秒后重试。
api-error-other = 集线器出了问题，详情见其日志。
api-error-detail = { $lead } 集线器的说明：{ $detail }

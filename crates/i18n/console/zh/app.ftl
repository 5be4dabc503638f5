# 控制台外壳：页面标题、页眉、导航、语言菜单、登录、密码、患者页的标签、错误。

app-title = telerehab — 治疗师控制台
app-loading = 正在加载…
app-nav =
    .aria-label = 主菜单
app-nav-clinic = 诊所
app-nav-names = 姓名
app-nav-audit = 审计日志
app-nav-change-password = 修改密码
app-nav-logout = 退出登录
app-language-label = 语言
app-who = { $email }（{ $role ->
        [admin] 管理员
       *[other] 治疗师
    }）
app-back-to-patients = 返回患者列表

## 登录

app-login-title = 登录
app-login-email = 电子邮箱
app-login-password = 密码
app-login-submit = 登录

## 密码

app-password-title = 修改密码
app-password-title-forced = 设置您自己的密码
app-password-forced = 您使用一次性密码登录。请先设置您自己的密码再继续。
app-password-one-time = 一次性密码
app-password-current = 当前密码
app-password-new = 新密码
app-password-rules = （至少 10 个字符，不能只有空格，不能是您的电子邮箱，不能是常见密码或规律组合；最好用几个互不相关的词）
app-password-repeat = 再次输入新密码
app-password-submit = 修改密码
app-password-differ = 两次输入的新密码不一致。

## 患者页

app-patient-title = 患者 { $name }
app-tabs-label = 患者
app-tab-live = 实时
app-tab-progress = 进展
app-tab-replay = 回放
app-tab-prescribe = 处方
app-tab-exercises = 练习
app-tab-stations = 训练站与配对

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
